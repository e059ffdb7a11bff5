#include "cell_control.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace skillcell::apps {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

/// The address of `path`; false when the path is too long for sun_path.
bool unixAddress(const fs::path& path, sockaddr_un& address) {
    address = {};
    address.sun_family = AF_UNIX;
    const std::string p = path.string();
    if (p.size() >= sizeof address.sun_path) return false;
    std::memcpy(address.sun_path, p.c_str(), p.size() + 1);
    return true;
}

/// Reads until '\n', EOF or `deadline`.
std::string readUntilNewline(int fd, Clock::time_point deadline, bool* complete) {
    std::string text;
    *complete = false;
    char buffer[4096];
    for (;;) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) return text;
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            *complete = n == 0;
            return text;
        }
        text.append(buffer, static_cast<std::size_t>(n));
        if (const auto nl = text.find('\n'); nl != std::string::npos) {
            text.resize(nl);
            *complete = true;
            return text;
        }
    }
}

void writeAll(int fd, const std::string& text) {
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::send(fd, text.data() + done, text.size() - done, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;
        done += static_cast<std::size_t>(n);
    }
}

}  // namespace

kb::Expected<ControlSocket> ControlSocket::listen(const fs::path& path) {
    sockaddr_un address{};
    if (!unixAddress(path, address)) {
        return kb::Error{path.string() + ": too long for a Unix socket; use a shorter --work-dir"};
    }
    std::error_code ec;
    if (fs::exists(path, ec)) {
        if (controlRequest(path, "ping", std::chrono::milliseconds(2000))) {
            return kb::Error{"a cell is up already in " + path.parent_path().string() +
                             " (`skillcell cell down` stops it)"};
        }
        fs::remove(path, ec);  // left by a supervisor that did not end cleanly
    }
    ControlSocket s;
    s.listener_.reset(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
    const mode_t previous = ::umask(077);  // the socket file: ours only
    const bool bound =
        s.listener_.valid() &&
        ::bind(s.listener_.get(), reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
    ::umask(previous);
    if (!bound || ::listen(s.listener_.get(), 8) != 0) {
        return kb::Error{"cannot listen on " + path.string() + ": " + process::errnoText(errno)};
    }
    s.path_ = path;
    return s;
}

ControlSocket::~ControlSocket() {
    if (path_.empty() || !listener_.valid()) return;
    std::error_code ec;
    fs::remove(path_, ec);
}

std::optional<ControlRequest> ControlSocket::accept() {
    process::UniqueFd connection(::accept4(listener_.get(), nullptr, nullptr, SOCK_CLOEXEC));
    if (!connection.valid()) return std::nullopt;
    bool complete = false;
    std::string line =
        readUntilNewline(connection.get(), Clock::now() + std::chrono::seconds(1), &complete);
    if (!complete) return std::nullopt;
    return ControlRequest{std::move(connection), std::move(line)};
}

void ControlSocket::reply(ControlRequest& request, const std::string& answer) {
    writeAll(request.connection.get(), answer + "\n");
    request.connection.reset();
}

kb::Expected<std::string> controlRequest(const fs::path& path, const std::string& line,
                                         std::chrono::milliseconds timeout) {
    sockaddr_un address{};
    if (!unixAddress(path, address)) return kb::Error{path.string() + ": path too long"};
    const process::UniqueFd fd(::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0));
    if (!fd.valid() ||
        ::connect(fd.get(), reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
        return kb::Error{"no cell is up in " + path.parent_path().string() + " (" +
                         process::errnoText(errno) + " at " + path.string() + ")"};
    }
    writeAll(fd.get(), line + "\n");
    bool complete = false;
    std::string answer = readUntilNewline(fd.get(), Clock::now() + timeout, &complete);
    if (!complete) {
        return kb::Error{"the cell in " + path.parent_path().string() + " did not answer '" + line +
                         "' within " + std::to_string(timeout.count()) + " ms"};
    }
    return answer;
}

}  // namespace skillcell::apps
