#include "mes/journal_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

namespace skillcell::mes {

kb::Expected<JournalLock> JournalLock::open(const std::string& journalPath) {
    const std::string path = journalPath + ".lock";
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
    if (fd < 0) {
        return kb::badInput("cannot open the journal's lock " + path + ": " + std::strerror(errno));
    }
    return JournalLock(fd, path);
}

kb::Expected<JournalLock::Attempt> JournalLock::tryAcquire() {
    if (held_) return Attempt::Acquired;
    if (::flock(fd_, LOCK_EX | LOCK_NB) == 0) {
        held_ = true;
        return Attempt::Acquired;
    }
    if (errno == EWOULDBLOCK) return Attempt::Held;
    return kb::Error{"cannot lock " + path_ + ": " + std::strerror(errno)};
}

JournalLock::JournalLock(JournalLock&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      path_(std::move(other.path_)),
      held_(std::exchange(other.held_, false)) {}

JournalLock& JournalLock::operator=(JournalLock&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = std::exchange(other.fd_, -1);
        path_ = std::move(other.path_);
        held_ = std::exchange(other.held_, false);
    }
    return *this;
}

JournalLock::~JournalLock() {
    if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace skillcell::mes
