#include "http/broken_pipe.hpp"

#include <csignal>
#include <mutex>

namespace skillcell::http {

void ignoreBrokenPipes() {
    static std::once_flag once;
    std::call_once(once, [] { std::signal(SIGPIPE, SIG_IGN); });
}

}  // namespace skillcell::http
