#pragma once
// The control socket of a running cell: a Unix-domain stream socket in the cell's work
// directory (control.sock, mode 0600, so only the user who started the cell may use it)
// through which `skillcell cell status` and `cell down` talk to `cell up`. A file system
// socket, not a network one: it reaches the supervisor from outside the cell's private
// network namespace. One request line per connection ("status", "down"); the answer is one
// JSON document, then the supervisor closes the connection.
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include "kb/expected.hpp"
#include "process/child_process.hpp"

namespace skillcell::apps {

/// The socket's file in a cell's work directory.
[[nodiscard]] inline std::filesystem::path controlSocketPath(const std::filesystem::path& dir) {
    return dir / "control.sock";
}

/// A request that came in, with the connection to answer it on.
struct ControlRequest {
    process::UniqueFd connection;
    std::string line;  // without its '\n'
};

class ControlSocket {
public:
    /// Listens at `path`. Fails when another supervisor answers there (the cell is up), or
    /// when the socket cannot be made; a stale file from a crashed supervisor is replaced.
    [[nodiscard]] static kb::Expected<ControlSocket> listen(const std::filesystem::path& path);
    ControlSocket(ControlSocket&&) noexcept = default;
    ControlSocket& operator=(ControlSocket&&) noexcept = default;
    ControlSocket(const ControlSocket&) = delete;
    ControlSocket& operator=(const ControlSocket&) = delete;
    /// Removes the socket's file.
    ~ControlSocket();

    /// poll() this for a connection waiting.
    [[nodiscard]] int fd() const { return listener_.get(); }
    /// The waiting connection's request, read for at most 1 s (a client that says nothing
    /// is dropped); nothing when there was none or it was dropped.
    [[nodiscard]] std::optional<ControlRequest> accept();
    /// Sends `answer` (one JSON document and '\n') and closes the connection; a client that
    /// went away is no error.
    static void reply(ControlRequest& request, const std::string& answer);

private:
    ControlSocket() = default;
    process::UniqueFd listener_;
    std::filesystem::path path_;
};

/// Sends one request line to the cell whose control socket is `path` and returns its
/// answer; waits at most `timeout`. The error says whether no cell is up there.
[[nodiscard]] kb::Expected<std::string> controlRequest(const std::filesystem::path& path,
                                                       const std::string& line,
                                                       std::chrono::milliseconds timeout);

}  // namespace skillcell::apps
