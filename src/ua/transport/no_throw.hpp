#pragma once
// kNoThrow: the completion token of our coroutines' I/O. An operation's error comes back as
// the first element of a tuple instead of an exception, so that what goes wrong on the
// network is handled as a value where it happens.
#include <asio/experimental/as_tuple.hpp>
#include <asio/use_awaitable.hpp>

namespace skillcell::ua {

inline constexpr auto kNoThrow = asio::experimental::as_tuple(asio::use_awaitable);

}  // namespace skillcell::ua
