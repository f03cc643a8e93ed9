#include "lib/output/output_file.h"

#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "core/error.h"

namespace mpvg {

namespace {

// The temporary files being written, for the signal handler: a fixed table
// (no allocation, no lock inside the handler). A slot is 0 free, 1 taken
// while its path is copied in, 2 live.
constexpr int kSlots = 256;
struct Slot {
  std::atomic<int> state{0};
  char path[PATH_MAX];
};
Slot g_slots[kSlots];

// The dispositions in force before ours, restored before re-raising.
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
struct sigaction g_previous[sizeof kSignals / sizeof kSignals[0]];

extern "C" void remove_partial_outputs(int sig) {
  for (Slot& s : g_slots)
    if (s.state.load(std::memory_order_acquire) == 2) unlink(s.path);
  for (size_t i = 0; i < sizeof kSignals / sizeof kSignals[0]; i++)
    if (kSignals[i] == sig) sigaction(sig, &g_previous[i], nullptr);
  raise(sig);
}

// Our handler goes only where the signal would end the process anyway
// (SIG_DFL): a program that ignores or handles a signal keeps doing so.
void install_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (size_t i = 0; i < sizeof kSignals / sizeof kSignals[0]; i++) {
      struct sigaction old {};
      if (sigaction(kSignals[i], nullptr, &old) != 0 || (old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL)
        continue;
      struct sigaction sa {};
      sa.sa_handler = remove_partial_outputs;
      sigemptyset(&sa.sa_mask);
      sa.sa_flags = SA_RESETHAND;
      g_previous[i] = old;
      sigaction(kSignals[i], &sa, nullptr);
    }
  });
}

// A registered temporary file: removed by the destructor unless committed
// (renamed into place), and by the handler on a fatal signal meanwhile.
class Partial {
 public:
  explicit Partial(const std::string& path) : path_(path) {
    install_handlers();
    if (path.size() >= PATH_MAX) return;  // not registered: still removed on errors
    for (int i = 0; i < kSlots; i++) {
      int free = 0;
      if (g_slots[i].state.compare_exchange_strong(free, 1)) {
        std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
        g_slots[i].state.store(2, std::memory_order_release);
        slot_ = i;
        break;
      }
    }
  }
  ~Partial() {
    if (!committed_) unlink(path_.c_str());
    if (slot_ >= 0) g_slots[slot_].state.store(0, std::memory_order_release);
  }
  Partial(const Partial&) = delete;
  Partial& operator=(const Partial&) = delete;
  void committed() { committed_ = true; }

 private:
  std::string path_;
  int slot_ = -1;
  bool committed_ = false;
};

// The folder of path ("." for a bare name).
std::string dir_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

[[noreturn]] void fail(const std::string& path, int err) {
  throw Error("cannot write '" + path + "': " + std::strerror(err));
}

// Writes all of data to fd; returns 0 or the errno of the failing write.
int write_all(int fd, const uint8_t* data, size_t size) {
  while (size > 0) {
    const ssize_t w = ::write(fd, data, size);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0) return errno;
    if (w == 0) return EIO;
    data += w;
    size -= size_t(w);
  }
  return 0;
}

// A name for the temporary file beside `path`: ".NAME.XXXXXX.part", NAME
// cut so that the whole stays within a file name's 255 bytes.
std::string partial_name(const std::string& path, uint64_t nonce) {
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  if (name.size() > 200) name.resize(200);
  static const char digits[] = "abcdefghijklmnopqrstuvwxyz0123456789";
  std::string tag;
  for (int i = 0; i < 8; i++, nonce /= 36) tag += digits[nonce % 36];
  return dir + "." + name + "." + tag + ".part";
}

uint64_t next_nonce() {
  static std::atomic<uint64_t> counter{0};
  uint64_t x = uint64_t(std::chrono::steady_clock::now().time_since_epoch().count()) ^
               (uint64_t(getpid()) << 32) ^ (counter.fetch_add(1) * 0x9E3779B97F4A7C15ull);
  x ^= x >> 31;
  x *= 0xBF58476D1CE4E5B9ull;
  return x ^ (x >> 29);
}

}  // namespace

void write_output(const std::string& path, const uint8_t* data, size_t size) {
  if (path == "-") {
    std::fflush(stdout);
    if (const int err = write_all(STDOUT_FILENO, data, size)) fail("-", err);
    return;
  }
  if (path.empty()) fail(path, ENOENT);
  struct stat st {};
  const bool exists = stat(path.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) fail(path, EISDIR);
  // A pipe, a terminal, /dev/stdout: written in place; so is an existing
  // file the caller may write in a folder where it may not create one
  // (nothing can be renamed there).
  const bool in_place = exists && (!S_ISREG(st.st_mode) || (access(dir_of(path).c_str(), W_OK) != 0 &&
                                                            access(path.c_str(), W_OK) == 0));
  if (in_place) {
    const int fd = open(path.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY | (S_ISREG(st.st_mode) ? O_TRUNC : 0));
    if (fd < 0) fail(path, errno);
    const int err = write_all(fd, data, size);
    const int closed = close(fd) == 0 ? 0 : errno;
    if (err || closed) fail(path, err ? err : closed);
    return;
  }
  // The temporary file, with the caller's umask as any new file.
  std::string tmp;
  int fd = -1;
  for (int attempt = 0; attempt < 64 && fd < 0; attempt++) {
    tmp = partial_name(path, next_nonce());
    fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOCTTY, 0666);
    if (fd < 0 && errno != EEXIST) fail(path, errno);
  }
  if (fd < 0) fail(path, EEXIST);
  Partial partial(tmp);
  int err = write_all(fd, data, size);
  // A file being replaced keeps its permission bits.
  if (!err && exists) fchmod(fd, st.st_mode & 07777);
  if (close(fd) != 0 && !err) err = errno;
  if (err) fail(path, err);
  if (rename(tmp.c_str(), path.c_str()) != 0) fail(path, errno);
  partial.committed();
}

}  // namespace mpvg
