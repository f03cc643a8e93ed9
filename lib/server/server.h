// The persistent renderer (svg2png --server, or MPVG_SERVER=1): for people
// who call svg2png in loops. The first such call starts a background
// process of the same executable that keeps CUDA's context, kernels and
// memory pool warm; later calls hand it their job over a Unix socket.
//
// It lends no rights. The server serves a client only when the client's
// credentials equal its own (Credentials below: uids and gids, groups,
// capabilities, no_new_privs, seccomp, namespaces, root, cgroup, resource
// limits, LSM context, and the environment variables rendering reads), as
// read from /proc for SO_PEERCRED's process, pinned by a pidfd; otherwise
// it refuses and the client renders in-process. The job's files are the
// client's: the client reads the input itself ("-" is its standard input)
// and sends the bytes, with its arguments and the absolute paths the
// document's references and read policy resolve against; the server sends
// back the job's messages (warnings, errors, --stats lines), the PNG's
// bytes and the exit status, and the client prints the messages and writes
// the PNG itself (atomically, with its own umask and rights). No file
// descriptor crosses the socket and nothing process-wide (working
// directory, standard streams, umask) changes per job. Only single-file
// jobs are handed over: batches (-o OUTDIR, --batch) render in-process,
// where the pipeline amortises start-up itself.
//
// Jobs run concurrently, each on a thread of its own. A job whose client
// has gone (hung up) is dropped at its next stage boundary. While a job
// runs the server sends a heartbeat every half second from a thread of its
// own; a client that hears nothing for MPVG_SERVER_TIMEOUT seconds (default
// 10), or whose server refuses or dies mid-job, renders in-process: as the
// client writes the output, nothing half-written is left behind.
//
// Private to the user: the socket lives in $XDG_RUNTIME_DIR/mpvg (else
// /tmp/mpvg-UID), a folder that must be the user's own with no access for
// others (else nothing is served: the call renders in-process). The server
// exits after MPVG_SERVER_IDLE seconds without a job (default 300). One
// server per executable build (the socket's name holds the executable's
// identity). MPVG_SERVER_LOG=FILE makes it log each job's fate (served,
// refused and why, cancelled) to FILE.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mpvg::server {

// Is the persistent renderer asked for: --server among the arguments, or
// MPVG_SERVER=1 in the environment?
bool requested(int argc, char** argv);

// A job as the client hands it over. Paths are absolute: the server's
// working directory is not the client's.
struct Request {
  std::vector<std::string> args;  // the client's argv
  std::string document;           // the input's path, "-" for standard input
  std::string base_dir;           // where its relative references resolve (for "-": the client's folder)
  std::vector<std::string> allow_read, font_dirs;  // --allow-read, --font-dir
  std::string text;               // the input's bytes, as the client read them
};

// What the server answers: what the job printed on stderr, the PNG's bytes
// (empty unless status is 0) and the exit status.
struct Reply {
  int status = 1;
  std::string messages;
  std::vector<uint8_t> png;
};

// The client: hands the job to this user's server, starting one if none
// answers. nullopt, with *why, when the job must render in-process (no
// server, a refusal, the server died or went silent).
std::optional<Reply> forward(const Request& job, std::string* why);

// A process's credentials, as (name, value) fields: everything that decides
// what the process may read, use or see, and the environment variables
// that change a render. The server compares its own with the client's.
struct Credentials {
  std::vector<std::pair<std::string, std::string>> fields;
};
// This process's (the server's side of the comparison).
Credentials own_credentials();
// The first field (by name) whose value differs or that one side lacks;
// empty when the two are equal.
std::string mismatch(const Credentials& server, const Credentials& client);
// One line per field, "NAME=VALUE" (newlines and backslashes in values
// escaped), and back.
std::string to_text(const Credentials& c);
Credentials from_text(const std::string& text);

// The hidden argument that makes an executable the server, and the one of
// its tests: "--server-credentials-internal" prints own_credentials();
// "--server-credentials-internal A B" compares two printed records (files)
// and prints mismatch(A, B), exit 0 when equal and 1 otherwise.
inline constexpr const char* kServeArgument = "--serve-internal";
inline constexpr const char* kCredentialsArgument = "--server-credentials-internal";
int credentials_main(int argc, char** argv);

// Thrown by a job's checkpoint when its client has gone: the job is
// dropped (whatever it holds must be released by unwinding).
struct Cancelled {
  const char* stage;
};

// A job in the server: runs `job` and returns its reply. `checkpoint(stage)`
// is to be called at stage boundaries; it throws Cancelled when the client
// has hung up. Called on several threads at once.
using Job = std::function<Reply(const Request& job, const std::function<void(const char* stage)>& checkpoint)>;

// The server's main loop: accepts connections until idle and runs each
// served job on a thread of its own. Returns the process's exit status.
int serve(const Job& run);

// True in the server process (for --stats).
bool serving();

}  // namespace mpvg::server
