#pragma once
// JournalLock: one MES at a time runs the orders of a journal. The lock is an flock on
// "<journal>.lock", which the kernel releases when its holder exits, however it exits: a
// standby MES started on the same journal takes the orders over the moment the active one
// dies, and never while it lives (it would run the same orders twice).
#include <string>

#include "kb/expected.hpp"

namespace skillcell::mes {

class JournalLock {
public:
    enum class Attempt : std::uint8_t { Acquired, Held };
    /// Opens "<journalPath>.lock" (creating it); BadInput when it cannot be opened.
    [[nodiscard]] static kb::Expected<JournalLock> open(const std::string& journalPath);
    /// Takes the lock unless another process holds it (never blocks).
    [[nodiscard]] kb::Expected<Attempt> tryAcquire();
    [[nodiscard]] bool held() const { return held_; }

    JournalLock(JournalLock&& other) noexcept;
    JournalLock& operator=(JournalLock&& other) noexcept;
    JournalLock(const JournalLock&) = delete;
    JournalLock& operator=(const JournalLock&) = delete;
    ~JournalLock();

private:
    JournalLock(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}

    int fd_ = -1;
    std::string path_;
    bool held_ = false;
};

}  // namespace skillcell::mes
