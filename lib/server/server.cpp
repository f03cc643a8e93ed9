#include "lib/server/server.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <thread>

#ifndef SO_PEERPIDFD
#define SO_PEERPIDFD 77  // Linux 6.5; older kernels answer ENOPROTOOPT
#endif

extern char** environ;

namespace mpvg::server {

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_serving{false};

// The folder of the user's sockets, made if missing; empty when it is not
// private (another owner, access for others, a symbolic link).
std::string socket_dir() {
  std::string dir;
  if (const char* d = std::getenv("MPVG_SERVER_DIR"); d && *d) {
    dir = d;  // tests
  } else if (const char* x = std::getenv("XDG_RUNTIME_DIR"); x && *x) {
    dir = std::string(x) + "/mpvg";
  } else {
    dir = "/tmp/mpvg-" + std::to_string(getuid());
  }
  if (mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) return {};
  struct stat st {};
  if (lstat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != getuid() || (st.st_mode & 077) != 0)
    return {};
  return dir;
}

// The socket's path: one per executable build (its path, size and
// modification time), so that a rebuilt svg2png never talks to an old
// server.
std::string socket_path() {
  const std::string dir = socket_dir();
  if (dir.empty()) return {};
  char exe[4096];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return {};
  exe[n] = 0;
  struct stat st {};
  if (stat(exe, &st) != 0) return {};
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  auto mix = [&](const void* p, size_t len) {
    for (size_t i = 0; i < len; i++) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 1099511628211ull;
  };
  mix(exe, size_t(n));
  mix(&st.st_size, sizeof st.st_size);
  mix(&st.st_mtim, sizeof st.st_mtim);
  char name[64];
  std::snprintf(name, sizeof name, "/svg2png-%016llx.sock", static_cast<unsigned long long>(h));
  const std::string path = dir + name;
  if (path.size() >= sizeof(sockaddr_un::sun_path)) return {};
  return path;
}

sockaddr_un address(const std::string& path) {
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::memcpy(a.sun_path, path.c_str(), path.size() + 1);
  return a;
}

void set_timeout(int fd, int option, double seconds) {
  timeval tv{};
  tv.tv_sec = static_cast<time_t>(seconds);
  tv.tv_usec = static_cast<suseconds_t>((seconds - double(tv.tv_sec)) * 1e6);
  setsockopt(fd, SOL_SOCKET, option, &tv, sizeof tv);
}

// A connection to path; sends (and connect(), which waits while the
// server's backlog is full) give up after timeout_s.
int connect_to(const std::string& path, double timeout_s) {
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  set_timeout(fd, SO_SNDTIMEO, timeout_s);
  const sockaddr_un a = address(path);
  if (connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

bool write_all(int fd, const void* data, size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t w = send(fd, p, n, MSG_NOSIGNAL);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    p += w;
    n -= size_t(w);
  }
  return true;
}

// Reads n bytes. With timeout_ms >= 0, gives up (Silent) when nothing at
// all arrives for that long; any byte restarts the wait.
enum class Got { Ok, Closed, Silent };
Got read_all(int fd, void* data, size_t n, int timeout_ms = -1) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    if (timeout_ms >= 0) {
      pollfd pf{fd, POLLIN, 0};
      const int ready = poll(&pf, 1, timeout_ms);
      if (ready < 0 && errno == EINTR) continue;
      if (ready == 0) return Got::Silent;
      if (ready < 0) return Got::Closed;
    }
    const ssize_t r = recv(fd, p, n, 0);
    if (r < 0 && errno == EINTR) continue;
    if (r < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return Got::Silent;  // SO_RCVTIMEO
    if (r <= 0) return Got::Closed;
    p += r;
    n -= size_t(r);
  }
  return Got::Ok;
}

// Starts a server: a grandchild of this process in a session of its own,
// its standard streams on /dev/null, running this executable.
void spawn_server() {
  const pid_t child = fork();
  if (child < 0) return;
  if (child == 0) {
    setsid();
    if (fork() != 0) _exit(0);
    const int null = open("/dev/null", O_RDWR);
    if (null >= 0) {
      dup2(null, 0);
      dup2(null, 1);
      dup2(null, 2);
    }
    char* args[] = {const_cast<char*>("svg2png"), const_cast<char*>(kServeArgument), nullptr};
    execv("/proc/self/exe", args);
    _exit(127);
  }
  waitpid(child, nullptr, 0);
}

// The wire. A request: "MPVG2\0", the argument count and the arguments,
// the document's path, its base folder, the --allow-read and --font-dir
// lists, the environment list (NAME=VALUE), then the document's bytes;
// strings and lists are length-prefixed (u32 counts and lengths, a u64 for
// the document). The server answers with frames of one type byte: 'H'
// (heartbeat, nothing else), 'R' (refused: a u32-prefixed reason), 'D'
// (done: the i32 status, then the messages and the PNG, u64-prefixed).
constexpr char kMagic[6] = "MPVG2";
constexpr uint32_t kMaxStrings = 1 << 20, kMaxStringBytes = 1 << 20;
constexpr uint64_t kMaxDocumentBytes = uint64_t(1) << 30, kMaxReplyBytes = uint64_t(1) << 40;

struct Writer {
  std::string bytes;
  template <typename T>
  void put(T v) {
    bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void put(const std::string& s) {
    put(uint32_t(s.size()));
    bytes += s;
  }
  void put(const std::vector<std::string>& list) {
    put(uint32_t(list.size()));
    for (const std::string& s : list) put(s);
  }
};

struct Reader {
  int fd;
  int timeout_ms = -1;
  Got got = Got::Ok;
  bool ok() const { return got == Got::Ok; }
  bool raw(void* p, size_t n) {
    if (got == Got::Ok) got = read_all(fd, p, n, timeout_ms);
    return ok();
  }
  template <typename T>
  T get() {
    T v{};
    raw(&v, sizeof v);
    return v;
  }
  // A u32- or u64-prefixed byte string of at most `limit` bytes.
  template <typename Size, typename Out>
  bool bytes(Out& out, uint64_t limit) {
    const Size n = get<Size>();
    if (!ok()) return false;
    if (n > limit) {
      got = Got::Closed;
      return false;
    }
    out.resize(n);
    return raw(out.data(), n);
  }
  bool string(std::string& s) { return bytes<uint32_t>(s, kMaxStringBytes); }
  bool list(std::vector<std::string>& l) {
    const uint32_t n = get<uint32_t>();
    if (ok() && n > kMaxStrings) got = Got::Closed;
    if (!ok()) return false;
    l.resize(n);
    for (std::string& s : l)
      if (!string(s)) return false;
    return true;
  }
};

// --- Credentials ---------------------------------------------------------

std::nullopt_t fail(std::string* why, std::string what) {
  *why = std::move(what);
  return std::nullopt;
}

// The environment variables a render reads (fonts: fontconfig's; CUDA's
// device selection; OpenImageIO's options; the loader's library paths) and
// every MPVG_* setting but the persistent renderer's own and MPVG_T0 (a
// benchmark's clock), as "env NAME" fields.
void add_environment(const std::vector<std::string>& env, Credentials& c) {
  static const std::set<std::string> names = {
      "FONTCONFIG_FILE", "FONTCONFIG_PATH", "FONTCONFIG_SYSROOT", "FC_LANG",  "XDG_DATA_HOME",   "XDG_DATA_DIRS",
      "XDG_CONFIG_HOME", "XDG_CONFIG_DIRS", "XDG_CACHE_HOME",     "HOME",     "LANG",            "LC_ALL",
      "LC_CTYPE",        "LD_LIBRARY_PATH", "LD_PRELOAD"};
  std::map<std::string, std::string> taken;  // the first of duplicates, as getenv
  for (const std::string& e : env) {
    const size_t eq = e.find('=');
    if (eq == std::string::npos) continue;
    const std::string name = e.substr(0, eq);
    const bool mpvg = name.rfind("MPVG_", 0) == 0 && name.rfind("MPVG_SERVER", 0) != 0 && name != "MPVG_T0";
    if (names.count(name) || mpvg || name.rfind("CUDA_", 0) == 0 || name.rfind("OPENIMAGEIO_", 0) == 0)
      taken.emplace(name, e.substr(eq + 1));
  }
  for (const auto& [name, value] : taken) c.fields.emplace_back("env " + name, value);
}

std::vector<std::string> own_environment() {
  std::vector<std::string> env;
  for (char** e = environ; e && *e; e++) env.emplace_back(*e);
  return env;
}

bool read_at(int dir, const char* name, std::string* out) {
  const int fd = openat(dir, name, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  out->clear();
  char buf[4096];
  ssize_t n;
  while ((n = read(fd, buf, sizeof buf)) > 0) out->append(buf, size_t(n));
  const int err = errno;
  close(fd);
  errno = err;
  return n == 0;
}

// Runs of white space as one space, none at the ends, no NUL (security
// contexts end with one or with a newline).
std::string normalised(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '\0') continue;
    if (ch == ' ' || ch == '\t' || ch == '\n') {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += ch;
    }
  }
  if (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

// A process's LSM context from /proc/PID/attr/current: "none" where no
// module keeps one (EINVAL, ENOENT, EOPNOTSUPP).
std::string lsm_of(int dir) {
  std::string s;
  if (read_at(dir, "attr/current", &s)) return normalised(s);
  return errno == EINVAL || errno == ENOENT || errno == EOPNOTSUPP ? "none" : "unreadable";
}

// The credentials of the process whose /proc folder is `dir`, `lsm` its
// security context; nullopt when one cannot be read (a field that this
// kernel lacks reads "absent" on both sides).
std::optional<Credentials> read_credentials(int dir, const std::string& lsm, std::string* why) {
  Credentials c;
  std::string status;
  if (!read_at(dir, "status", &status)) return fail(why, "cannot read its status");
  for (const char* field : {"Uid", "Gid", "Groups", "CapInh", "CapPrm", "CapEff", "CapBnd", "CapAmb", "NoNewPrivs",
                            "Seccomp", "Seccomp_filters"}) {
    const std::string key = std::string("\n") + field + ":";
    const size_t at = ("\n" + status).find(key);
    std::string value = "absent";
    if (at != std::string::npos) {
      const size_t begin = at + key.size() - 1, end = std::min(status.find('\n', begin), status.size());
      value = normalised(status.substr(begin, end - begin));
    }
    c.fields.emplace_back(field, value);
  }
  // Namespaces and the root folder by identity (device and inode).
  auto identity = [&](const std::string& name) -> std::optional<std::string> {
    struct stat st {};
    if (fstatat(dir, name.c_str(), &st, 0) != 0) {
      if (errno == ENOENT) return "absent";
      return std::nullopt;
    }
    return std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
  };
  for (const char* ns : {"mnt", "user", "pid", "net", "ipc", "uts", "cgroup"}) {
    const std::optional<std::string> id = identity(std::string("ns/") + ns);
    if (!id) return fail(why, std::string("cannot see its ") + ns + " namespace");
    c.fields.emplace_back(std::string("ns/") + ns, *id);
  }
  const std::optional<std::string> root = identity("root");
  if (!root) return fail(why, "cannot see its root folder");
  c.fields.emplace_back("root", *root);
  std::string text;
  if (!read_at(dir, "cgroup", &text)) return fail(why, "cannot read its cgroup");
  c.fields.emplace_back("cgroup", text);
  if (!read_at(dir, "limits", &text)) return fail(why, "cannot read its limits");
  c.fields.emplace_back("limits", text);
  c.fields.emplace_back("lsm", lsm);
  return c;
}

// The process of a pidfd as /proc/self/fdinfo tells it; 0 when unknown.
pid_t pid_of_pidfd(int pidfd) {
  std::string info;
  if (!read_at(AT_FDCWD, ("/proc/self/fdinfo/" + std::to_string(pidfd)).c_str(), &info)) return 0;
  const size_t at = info.find("\nPid:");
  return at == std::string::npos ? 0 : static_cast<pid_t>(std::atol(info.c_str() + at + 5));
}

bool hung_up(int conn) {
  pollfd p{conn, POLLRDHUP, 0};
  return poll(&p, 1, 0) > 0 && (p.revents & (POLLHUP | POLLRDHUP | POLLERR | POLLNVAL));
}

// The peer's credentials, its environment the list it sent. The process is
// pinned by a pidfd (the connecting process itself with SO_PEERPIDFD, else
// pidfd_open on SO_PEERCRED's pid) before /proc is read and checked
// alive afterwards, so that a pid reused meanwhile is not read for it.
std::optional<Credentials> peer_credentials(int conn, const std::vector<std::string>& env, std::string* why) {
  ucred peer{};
  socklen_t len = sizeof peer;
  if (getsockopt(conn, SOL_SOCKET, SO_PEERCRED, &peer, &len) != 0 || peer.pid <= 0)
    return fail(why, "no peer credentials");
  int pidfd = -1;
  len = sizeof pidfd;
  if (getsockopt(conn, SOL_SOCKET, SO_PEERPIDFD, &pidfd, &len) != 0) pidfd = -1;
  if (pidfd < 0) pidfd = static_cast<int>(syscall(SYS_pidfd_open, peer.pid, 0));
  if (pidfd < 0) return fail(why, "cannot pin the client's process");
  std::optional<Credentials> c;
  const int dir = open(("/proc/" + std::to_string(peer.pid)).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir < 0 || pid_of_pidfd(pidfd) != peer.pid) {
    *why = "cannot find the client's process";
  } else {
    // The context the connection carries (SO_PEERSEC); where the kernel
    // keeps none for sockets (ENOPROTOOPT), the process's own.
    char ctx[4096];
    socklen_t ctx_len = sizeof ctx;
    std::string lsm;
    if (getsockopt(conn, SOL_SOCKET, SO_PEERSEC, ctx, &ctx_len) == 0) lsm = normalised(std::string(ctx, ctx_len));
    else lsm = errno == ENOPROTOOPT ? lsm_of(dir) : "unreadable";
    c = read_credentials(dir, lsm, why);
    if (c) add_environment(env, *c);
  }
  pollfd p{pidfd, POLLIN, 0};  // readable once the process has exited
  if (c && (poll(&p, 1, 0) != 0 || hung_up(conn))) {
    *why = "the client's process ended";
    c.reset();
  }
  if (dir >= 0) close(dir);
  close(pidfd);
  return c;
}

// --- The server ----------------------------------------------------------

// MPVG_SERVER_LOG: one line per event, "[PID] job N: ...", appended in one
// write.
void log_line(const char* format, ...) {
  const char* path = std::getenv("MPVG_SERVER_LOG");
  if (!path || !*path) return;
  char line[1024];
  int n = std::snprintf(line, sizeof line, "[%d] ", static_cast<int>(getpid()));
  va_list args;
  va_start(args, format);
  n += std::vsnprintf(line + n, sizeof line - 1 - size_t(n), format, args);
  va_end(args);
  n = std::clamp(n, 0, int(sizeof line) - 2);
  line[n++] = '\n';
  const int fd = open(path, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0600);
  if (fd < 0) return;
  (void)!write(fd, line, size_t(n));
  close(fd);
}

// A client's connection while its job lives: the job's thread and the
// heartbeat thread both send on it, one frame at a time.
struct Connection {
  explicit Connection(int f) : fd(f) {}
  ~Connection() { close(fd); }
  const int fd;
  std::mutex send;
  std::atomic<bool> gone{false};
};

// The jobs in flight, for the heartbeats and the idle timer.
struct Jobs {
  std::mutex mutex;
  std::condition_variable changed;
  std::set<std::shared_ptr<Connection>> live;
  Clock::time_point last_end = Clock::now();
};
Jobs g_jobs;
constexpr size_t kMaxJobs = 64;

// Every half second while jobs run, one 'H' byte to each client, never
// waiting: a connection busy with a reply is skipped (bytes are flowing),
// a full socket buffer drops the beat. A send that fails marks the client
// gone.
void heartbeats() {
  std::unique_lock<std::mutex> lock(g_jobs.mutex);
  for (;;) {
    g_jobs.changed.wait(lock, [] { return !g_jobs.live.empty(); });
    const std::vector<std::shared_ptr<Connection>> live(g_jobs.live.begin(), g_jobs.live.end());
    lock.unlock();
    for (const auto& c : live) {
      std::unique_lock<std::mutex> sending(c->send, std::try_to_lock);
      if (!sending) continue;
      const char beat = 'H';
      if (send(c->fd, &beat, 1, MSG_DONTWAIT | MSG_NOSIGNAL) < 0 && errno != EAGAIN && errno != EWOULDBLOCK)
        c->gone = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    lock.lock();
  }
}

// A frame: its head, then (not copied into it) a trailing payload.
bool send_frame(Connection& c, const std::string& head, const void* tail = nullptr, size_t tail_size = 0) {
  std::lock_guard<std::mutex> lock(c.send);
  return write_all(c.fd, head.data(), head.size()) && write_all(c.fd, tail, tail_size);
}

void refuse(Connection& c, const std::string& reason) {
  Writer w;
  w.put('R');
  w.put(reason);
  send_frame(c, w.bytes);
}

bool read_request(int fd, Request* job, std::vector<std::string>* env) {
  Reader r{fd};
  char magic[sizeof kMagic] = {};
  if (!r.raw(magic, sizeof magic) || std::memcmp(magic, kMagic, sizeof kMagic) != 0) return false;
  return r.list(job->args) && !job->args.empty() && r.string(job->document) && r.string(job->base_dir) &&
         r.list(job->allow_read) && r.list(job->font_dirs) && r.list(*env) &&
         r.bytes<uint64_t>(job->text, kMaxDocumentBytes);
}

// One connection, on a thread of its own: the request, the credentials,
// the job, the reply.
void handle(const std::shared_ptr<Connection>& c, unsigned long number, const Job& run) {
  // A client that stalls mid-request, or stops reading the reply, does not
  // hold the thread for ever.
  set_timeout(c->fd, SO_RCVTIMEO, 5);
  set_timeout(c->fd, SO_SNDTIMEO, 30);
  Request job;
  std::vector<std::string> env;
  if (!read_request(c->fd, &job, &env)) {
    log_line("job %lu: no valid request", number);
    return;
  }
  std::string why;
  const std::optional<Credentials> client = peer_credentials(c->fd, env, &why);
  if (client) {
    const std::string field = mismatch(own_credentials(), *client);
    if (!field.empty()) why = "credentials differ: " + field;
  }
  if (!client || !why.empty()) {
    log_line("job %lu: refused: %s", number, why.c_str());
    refuse(*c, why);
    return;
  }
  log_line("job %lu: started", number);
  const auto checkpoint = [&c](const char* stage) {
    if (c->gone || hung_up(c->fd)) throw Cancelled{stage};
  };
  Reply reply;
  try {
    reply = run(job, checkpoint);
    checkpoint("before the reply");
  } catch (const Cancelled& e) {
    log_line("job %lu: cancelled %s: the client has gone", number, e.stage);
    return;
  } catch (const std::exception& e) {
    reply = Reply{1, std::string("svg2png: ") + e.what() + "\n", {}};
  }
  Writer w;
  w.put('D');
  w.put(int32_t(reply.status));
  w.put(uint64_t(reply.messages.size()));
  w.bytes += reply.messages;
  w.put(uint64_t(reply.png.size()));
  const bool sent = send_frame(*c, w.bytes, reply.png.data(), reply.png.size());
  log_line("job %lu: %s (status %d)", number, sent ? "served" : "done, but the client has gone", reply.status);
}

}  // namespace

// --- Credentials (public) --------------------------------------------------

Credentials own_credentials() {
  const int dir = open("/proc/self", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  std::string why;
  std::optional<Credentials> c = dir >= 0 ? read_credentials(dir, lsm_of(dir), &why) : std::nullopt;
  if (dir >= 0) close(dir);
  // Unreadable: a record no client matches.
  if (!c) return Credentials{{{"unreadable", why}}};
  add_environment(own_environment(), *c);
  return *c;
}

std::string mismatch(const Credentials& server, const Credentials& client) {
  const std::map<std::string, std::string> a(server.fields.begin(), server.fields.end());
  const std::map<std::string, std::string> b(client.fields.begin(), client.fields.end());
  auto ia = a.begin();
  auto ib = b.begin();
  for (; ia != a.end() && ib != b.end(); ++ia, ++ib) {
    if (ia->first != ib->first) return std::min(ia->first, ib->first);  // one side lacks it
    if (ia->second != ib->second) return ia->first;
  }
  if (ia != a.end()) return ia->first;
  if (ib != b.end()) return ib->first;
  return {};
}

std::string to_text(const Credentials& c) {
  std::string out;
  for (const auto& [name, value] : c.fields) {
    out += name + "=";
    for (char ch : value) {
      if (ch == '\\') out += "\\\\";
      else if (ch == '\n') out += "\\n";
      else out += ch;
    }
    out += '\n';
  }
  return out;
}

Credentials from_text(const std::string& text) {
  Credentials c;
  for (size_t pos = 0; pos < text.size();) {
    const size_t end = std::min(text.find('\n', pos), text.size());
    const std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    std::string value;
    for (size_t i = eq + 1; i < line.size(); i++) {
      if (line[i] == '\\' && i + 1 < line.size()) {
        value += line[i + 1] == 'n' ? '\n' : line[i + 1];
        i++;
      } else {
        value += line[i];
      }
    }
    c.fields.emplace_back(line.substr(0, eq), value);
  }
  return c;
}

int credentials_main(int argc, char** argv) {
  if (argc == 2) {
    std::fputs(to_text(own_credentials()).c_str(), stdout);
    return 0;
  }
  if (argc != 4) {
    std::fprintf(stderr, "usage: svg2png %s [RECORD_A RECORD_B]\n", kCredentialsArgument);
    return 2;
  }
  Credentials c[2];
  for (int i = 0; i < 2; i++) {
    std::ifstream f(argv[2 + i], std::ios::binary);
    if (!f) {
      std::fprintf(stderr, "svg2png: cannot read '%s'\n", argv[2 + i]);
      return 2;
    }
    c[i] = from_text(std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()));
  }
  const std::string field = mismatch(c[0], c[1]);
  std::printf("%s\n", field.empty() ? "equal" : field.c_str());
  return field.empty() ? 0 : 1;
}

// --- The client ------------------------------------------------------------

bool requested(int argc, char** argv) {
  for (int i = 1; i < argc; i++)
    if (std::strcmp(argv[i], "--server") == 0) return true;
  const char* e = std::getenv("MPVG_SERVER");
  return e && std::strcmp(e, "1") == 0;
}

bool serving() { return g_serving; }

std::optional<Reply> forward(const Request& job, std::string* why) {
  if (job.text.size() > kMaxDocumentBytes) return fail(why, "the document is too large to hand over");
  const std::string path = socket_path();
  if (path.empty()) return fail(why, "the socket folder is not private");
  double timeout_s = 10;
  if (const char* e = std::getenv("MPVG_SERVER_TIMEOUT"); e && std::atof(e) > 0) timeout_s = std::atof(e);
  int fd = connect_to(path, timeout_s);
  if (fd < 0) {
    spawn_server();
    // The server listens before it starts CUDA: it answers within
    // milliseconds of its start.
    const auto deadline = Clock::now() + std::chrono::seconds(3);
    while (fd < 0 && Clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      fd = connect_to(path, timeout_s);
    }
    if (fd < 0) return fail(why, "no persistent renderer could be started");
  }
  Writer w;
  w.bytes.append(kMagic, sizeof kMagic);
  w.put(job.args);
  w.put(job.document);
  w.put(job.base_dir);
  w.put(job.allow_read);
  w.put(job.font_dirs);
  std::vector<std::string> env = own_environment();
  w.put(env);
  w.put(uint64_t(job.text.size()));
  const bool sent = write_all(fd, w.bytes.data(), w.bytes.size()) && write_all(fd, job.text.data(), job.text.size());
  // The answer: heartbeats while the job runs, then a refusal or the
  // result. Silence for timeout_s means a hung server.
  Reader r{fd, static_cast<int>(timeout_s * 1000)};
  std::optional<Reply> reply;
  char type = 0;
  while (sent && r.raw(&type, 1) && type == 'H') {
  }
  try {
    if (!sent) {
      *why = "the persistent renderer did not take the job";
    } else if (r.got == Got::Silent) {
      char s[96];
      std::snprintf(s, sizeof s, "no word from the persistent renderer for %g s", timeout_s);
      *why = s;
    } else if (!r.ok()) {
      *why = "the persistent renderer ended during the job";
    } else if (type == 'R') {
      std::string reason;
      r.string(reason);
      *why = "refused: " + reason;
    } else if (type == 'D') {
      Reply d;
      d.status = r.get<int32_t>();
      if (r.bytes<uint64_t>(d.messages, kMaxReplyBytes) && r.bytes<uint64_t>(d.png, kMaxReplyBytes)) reply = d;
      else *why = "the persistent renderer's answer was cut short";
    } else {
      *why = "a garbled answer from the persistent renderer";
    }
  } catch (const std::bad_alloc&) {
    *why = "no memory for the persistent renderer's answer";
  }
  close(fd);
  return reply;
}

// --- The server (public) ---------------------------------------------------

int serve(const Job& run) {
  const std::string path = socket_path();
  if (path.empty()) return 1;
  signal(SIGPIPE, SIG_IGN);
  const int listener = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listener < 0) return 1;
  const sockaddr_un a = address(path);
  // A socket file nobody answers on is a dead server's: replaced. One that
  // answers is a live server's: this one is not needed.
  if (bind(listener, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    const int probe = connect_to(path, 1);
    if (probe >= 0) {
      close(probe);
      return 0;
    }
    unlink(path.c_str());
    if (bind(listener, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) return 1;
  }
  chmod(path.c_str(), 0600);
  if (listen(listener, 64) != 0) return 1;
  double idle_s = 300;
  if (const char* e = std::getenv("MPVG_SERVER_IDLE")) idle_s = std::max(0.1, std::atof(e));
  // Nothing of the process changes per job; a folder of its own keeps it
  // from pinning the one it was started in.
  if (chdir("/") != 0) return 1;
  g_serving = true;
  std::thread(heartbeats).detach();
  unsigned long jobs = 0;
  for (;;) {
    int timeout_ms = 1000;
    {
      std::lock_guard<std::mutex> lock(g_jobs.mutex);
      if (g_jobs.live.empty()) {
        const double left = idle_s - std::chrono::duration<double>(Clock::now() - g_jobs.last_end).count();
        if (left <= 0) break;  // idle: done
        timeout_ms = static_cast<int>(std::min(1000.0, left * 1000 + 1));
      }
    }
    pollfd p{listener, POLLIN, 0};
    if (poll(&p, 1, timeout_ms) <= 0) continue;
    const int fd = accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) continue;
    // Another user's process is dropped at once; the full comparison
    // of credentials is the job thread's.
    ucred peer{};
    socklen_t len = sizeof peer;
    if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &peer, &len) != 0 || peer.uid != getuid()) {
      close(fd);
      continue;
    }
    auto c = std::make_shared<Connection>(fd);
    {
      std::lock_guard<std::mutex> lock(g_jobs.mutex);
      if (g_jobs.live.size() >= kMaxJobs) continue;  // the client renders in-process
      g_jobs.live.insert(c);
    }
    g_jobs.changed.notify_all();
    const unsigned long number = ++jobs;
    std::thread([c, number, &run] {
      try {
        handle(c, number, run);
      } catch (...) {
        // No memory for the request or the reply: the client renders
        // in-process.
      }
      std::lock_guard<std::mutex> lock(g_jobs.mutex);
      g_jobs.live.erase(c);
      g_jobs.last_end = Clock::now();
    }).detach();
  }
  // Idle: the socket goes first, so that a client arriving now starts a
  // new server instead of waiting on this one.
  unlink(path.c_str());
  close(listener);
  return 0;
}

}  // namespace mpvg::server
