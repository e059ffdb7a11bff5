#pragma once
// A peer that closes its connection while we write to it must not end the process. OpenSSL
// writes to its sockets with write(2), which raises SIGPIPE there (the rest of skillcell
// sends with MSG_NOSIGNAL), so the first HTTP client or server of a process sets SIGPIPE
// to be ignored, once. Child processes get the default back before exec
// (process/child_process.cpp).
namespace skillcell::http {

void ignoreBrokenPipes();

}  // namespace skillcell::http
