// Asio's non-template code, compiled once for the whole project (ASIO_SEPARATE_COMPILATION,
// set in the top-level CMakeLists.txt).
#include <asio/impl/src.hpp>
