#pragma once
// blockingCall: runs a blocking function (device I/O, a WorldLink round trip, waiting for a
// child process) on an I/O thread of the component's own, and resumes the calling coroutine
// on its own executor with the result, so a server's thread never blocks.
#include <asio/awaitable.hpp>
#include <asio/co_spawn.hpp>
#include <asio/thread_pool.hpp>
#include <asio/use_awaitable.hpp>
#include <optional>
#include <type_traits>

namespace skillcell::devices {

template <class F>
asio::awaitable<std::invoke_result_t<F&>> blockingCall(asio::thread_pool& pool, F f) {
    using T = std::invoke_result_t<F&>;
    // Through an optional: co_spawn's result must be default-constructible, a Result is not.
    // The task is a named local: GCC 12 destroys temporaries of a co_await expression twice.
    auto task = [f = std::move(f)]() mutable -> asio::awaitable<std::optional<T>> {
        co_return f();
    };
    std::optional<T> result =
        co_await asio::co_spawn(pool.get_executor(), std::move(task), asio::use_awaitable);
    co_return std::move(*result);
}

}  // namespace skillcell::devices
