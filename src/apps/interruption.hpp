#pragma once
// Interruption: SIGINT and SIGTERM blocked in every thread of a command that runs a cell
// (its children unblock them), so that the command notices them between its bounded waits
// and stops its cell in order, the tool changer first, instead of dying with its components
// orphaned. Make it before any thread starts: threads inherit the mask.
#include <pthread.h>
#include <signal.h>

namespace skillcell::apps {

class Interruption {
public:
    Interruption() {
        sigemptyset(&set_);
        sigaddset(&set_, SIGINT);
        sigaddset(&set_, SIGTERM);
        pthread_sigmask(SIG_BLOCK, &set_, &previous_);
    }
    ~Interruption() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
    Interruption(const Interruption&) = delete;
    Interruption& operator=(const Interruption&) = delete;

    /// True once SIGINT or SIGTERM came (it stays pending; it is not consumed).
    [[nodiscard]] bool requested() const {
        sigset_t pending;
        sigpending(&pending);
        return sigismember(&pending, SIGINT) == 1 || sigismember(&pending, SIGTERM) == 1;
    }
    /// Waits for SIGINT or SIGTERM, and takes it.
    void wait() const {
        int sig = 0;
        sigwait(&set_, &sig);
    }
    /// The signals, for a signalfd that wakes a poll() when one comes.
    [[nodiscard]] const sigset_t& signals() const { return set_; }

private:
    sigset_t set_{};
    sigset_t previous_{};
};

}  // namespace skillcell::apps
