// The persistent renderer (svg2png --server, or MPVG_SERVER=1): for people
// who call svg2png in loops. The first such call starts a background
// process of the same executable that keeps CUDA's context, kernels and
// memory pool warm; later calls hand it their job over a Unix socket and
// wait for its exit status. The job runs in the server exactly as it would
// in the caller: the client passes its standard input, output and error
// and its working directory as file descriptors (SCM_RIGHTS), so files are
// read and written with the caller's paths and the bytes are the same.
//
// Private to the user: the socket lives in $XDG_RUNTIME_DIR/mpvg (else
// /tmp/mpvg-UID), a folder that must be the user's own with no access for
// others (else nothing is served: the call renders in-process); the server
// checks every peer's uid (SO_PEERCRED) and serves no one else. It exits
// after MPVG_SERVER_IDLE seconds without a job (default 300). One server per
// executable build (the socket's name holds the executable's identity), one
// job at a time. Whatever goes wrong on the way (no server can start, the
// socket is refused, the server dies), the call renders in-process.
#pragma once
#include <functional>
#include <optional>

namespace mpvg::server {

// Is the persistent renderer asked for: --server among the arguments, or
// MPVG_SERVER=1 in the environment?
bool requested(int argc, char** argv);

// The client: hands argv to this user's server, starting one if none
// answers, and returns the job's exit status; nullopt when the job could
// not be handed over (render in-process then).
std::optional<int> forward(int argc, char** argv);

// The hidden argument that makes an executable the server.
inline constexpr const char* kServeArgument = "--serve-internal";

// The server's main loop: runs each job with `run` (its argv as the client
// gave it; fds 0, 1, 2 and the working directory the client's while it
// runs), one at a time, until idle. Returns the process's exit status.
int serve(const std::function<int(int argc, char** argv)>& run);

// True inside serve()'s jobs (for --stats).
bool serving();

}  // namespace mpvg::server
