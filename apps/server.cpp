#include "apps/server.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

namespace mpvg::server {

namespace {

bool g_serving = false;

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

int connect_to(const std::string& path) {
  const int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
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

bool read_all(int fd, void* data, size_t n) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t r = recv(fd, p, n, 0);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r;
    n -= size_t(r);
  }
  return true;
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

// A job's wire format: "MPVG1", the argument count, then each argument's
// length and bytes; the four descriptors travel with the first byte.
constexpr char kMagic[6] = "MPVG1";
constexpr uint32_t kMaxArgs = 1 << 20, kMaxArgBytes = 1 << 20;

}  // namespace

bool requested(int argc, char** argv) {
  for (int i = 1; i < argc; i++)
    if (std::strcmp(argv[i], "--server") == 0) return true;
  const char* e = std::getenv("MPVG_SERVER");
  return e && std::strcmp(e, "1") == 0;
}

bool serving() { return g_serving; }

std::optional<int> forward(int argc, char** argv) {
  const std::string path = socket_path();
  if (path.empty()) return std::nullopt;
  int fd = connect_to(path);
  if (fd < 0) {
    spawn_server();
    // The server listens before it starts CUDA: it answers within
    // milliseconds of its start.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    while (fd < 0 && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      fd = connect_to(path);
    }
    if (fd < 0) return std::nullopt;
  }
  const int cwd = open(".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (cwd < 0) {
    close(fd);
    return std::nullopt;
  }
  // The header and the descriptors in one message.
  const int fds[4] = {0, 1, 2, cwd};
  char control[CMSG_SPACE(sizeof fds)] = {};
  char magic[sizeof kMagic];
  std::memcpy(magic, kMagic, sizeof kMagic);
  iovec iov{magic, sizeof magic};
  msghdr msg{};
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof control;
  cmsghdr* cm = CMSG_FIRSTHDR(&msg);
  cm->cmsg_level = SOL_SOCKET;
  cm->cmsg_type = SCM_RIGHTS;
  cm->cmsg_len = CMSG_LEN(sizeof fds);
  std::memcpy(CMSG_DATA(cm), fds, sizeof fds);
  bool ok = sendmsg(fd, &msg, MSG_NOSIGNAL) == ssize_t(sizeof magic);
  close(cwd);
  std::vector<char> body;
  auto put32 = [&](uint32_t v) { body.insert(body.end(), reinterpret_cast<char*>(&v), reinterpret_cast<char*>(&v) + 4); };
  put32(uint32_t(argc));
  for (int i = 0; i < argc; i++) {
    const size_t len = std::strlen(argv[i]);
    put32(uint32_t(len));
    body.insert(body.end(), argv[i], argv[i] + len);
  }
  ok = ok && write_all(fd, body.data(), body.size());
  // The server answers "started" (0 bytes of doubt: once it has the job,
  // the job is its), then the exit status.
  int32_t status = 0;
  uint8_t started = 0;
  if (!ok || !read_all(fd, &started, 1) || started != 1) {
    close(fd);
    return std::nullopt;
  }
  if (!read_all(fd, &status, sizeof status)) {
    // The server died inside the job: what it wrote may be partial.
    std::fprintf(stderr, "svg2png: the persistent renderer ended during the job\n");
    close(fd);
    return 1;
  }
  close(fd);
  return status;
}

int serve(const std::function<int(int argc, char** argv)>& run) {
  const std::string path = socket_path();
  if (path.empty()) return 1;
  signal(SIGPIPE, SIG_IGN);
  const int listener = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listener < 0) return 1;
  const sockaddr_un a = address(path);
  // A socket file nobody answers on is a dead server's: replaced. One that
  // answers is a live server's: this one is not needed.
  if (bind(listener, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
    const int probe = connect_to(path);
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
  const int home = open("/", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  fchdir(home);
  g_serving = true;
  for (;;) {
    pollfd p{listener, POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(idle_s * 1000));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) break;  // idle: done
    const int conn = accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
    if (conn < 0) continue;
    // Only this user.
    ucred peer{};
    socklen_t len = sizeof peer;
    if (getsockopt(conn, SOL_SOCKET, SO_PEERCRED, &peer, &len) != 0 || peer.uid != getuid()) {
      close(conn);
      continue;
    }
    // A client that stalls mid-request does not hold the server.
    timeval tv{5, 0};
    setsockopt(conn, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    int fds[4] = {-1, -1, -1, -1};
    char magic[sizeof kMagic] = {};
    char control[CMSG_SPACE(sizeof fds)] = {};
    iovec iov{magic, sizeof magic};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t got = recvmsg(conn, &msg, MSG_CMSG_CLOEXEC);
    bool ok = got == ssize_t(sizeof magic) && std::memcmp(magic, kMagic, sizeof kMagic) == 0;
    cmsghdr* cm = CMSG_FIRSTHDR(&msg);
    int nfds = 0;
    if (cm && cm->cmsg_level == SOL_SOCKET && cm->cmsg_type == SCM_RIGHTS) {
      nfds = static_cast<int>((cm->cmsg_len - CMSG_LEN(0)) / sizeof(int));
      std::memcpy(fds, CMSG_DATA(cm), std::min(nfds, 4) * sizeof(int));
    }
    ok = ok && nfds == 4;
    std::vector<std::string> args;
    uint32_t argc = 0;
    ok = ok && read_all(conn, &argc, 4) && argc >= 1 && argc <= kMaxArgs;
    for (uint32_t i = 0; ok && i < argc; i++) {
      uint32_t n = 0;
      ok = read_all(conn, &n, 4) && n <= kMaxArgBytes;
      std::string s(n, '\0');
      ok = ok && read_all(conn, s.data(), n);
      args.push_back(std::move(s));
    }
    const uint8_t started = 1;
    ok = ok && write_all(conn, &started, 1);
    if (!ok) {
      for (int f : fds)
        if (f >= 0) close(f);
      close(conn);
      continue;
    }
    // The job, with the client's streams and folder.
    std::fflush(stdout);
    std::fflush(stderr);
    const int saved[3] = {dup(0), dup(1), dup(2)};
    for (int k = 0; k < 3; k++) dup2(fds[k], k);
    fchdir(fds[3]);
    clearerr(stdin);
    std::cin.clear();
    std::vector<char*> argv;
    for (std::string& s : args) argv.push_back(s.data());
    argv.push_back(nullptr);
    int32_t status = 1;
    try {
      status = run(static_cast<int>(args.size()), argv.data());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "svg2png: %s\n", e.what());
    }
    std::fflush(stdout);
    std::fflush(stderr);
    for (int k = 0; k < 3; k++) {
      dup2(saved[k], k);
      close(saved[k]);
    }
    clearerr(stdin);
    std::cin.clear();
    fchdir(home);
    for (int f : fds) close(f);
    write_all(conn, &status, sizeof status);
    close(conn);
  }
  // Idle: the socket goes first, so that a client arriving now starts a
  // new server instead of waiting on this one.
  unlink(path.c_str());
  close(listener);
  return 0;
}

}  // namespace mpvg::server
