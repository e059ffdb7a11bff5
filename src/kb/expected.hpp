#pragma once
// kb::Expected<T>: the knowledge base's failures come from outside engines (a SPARQL syntax
// error, a reasoner's verdict, a child process that would not start) and are reported to
// people, so they carry text (common/expected.hpp).
#include "common/expected.hpp"

namespace skillcell::kb {

using skillcell::badInput;
using skillcell::Done;
using skillcell::Error;
using skillcell::ErrorKind;
using skillcell::Expected;
using skillcell::Status;

}  // namespace skillcell::kb
