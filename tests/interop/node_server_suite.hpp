#pragma once
// NodeServerSuite: a GoogleTest fixture base whose suite shares one node-opcua server
// (server.js, ~6 s to start). It skips loudly when node or node-opcua is missing, and fails
// instead when SKILLCELL_REQUIRE_NODE=1 (CI). Derived fixtures call NodeServerSuite::SetUp()
// first and use url().
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "node_peer.hpp"
#include "process/child_process.hpp"

namespace skillcell::test {

class NodeServerSuite : public ::testing::Test {
protected:
    static void SetUpTestSuite() { startServer({}); }

    /// Starts server.js with `extraArgs` (e.g. --secure); a derived suite's
    /// SetUpTestSuite() calls it with its own.
    static void startServer(const std::vector<std::string>& extraArgs) {
        const char* require = std::getenv("SKILLCELL_REQUIRE_NODE");
        const bool required = require != nullptr && std::string_view(require) == "1";
        auto peer = startNodeServer(SKILLCELL_INTEROP_DIR, extraArgs);
        if (!peer && peer.errorKind() == ErrorKind::Unavailable) {
            unavailable_ = peer.error();
            std::cerr << "\n!!! " << (required ? "FAILING" : "SKIPPING")
                      << " node-opcua interop: " << unavailable_ << " !!!\n\n";
            unavailableIsFailure_ = required;
            return;
        }
        if (!peer) {
            startError_ = peer.error();
            return;
        }
        url_ = peer->url;
        server_.emplace(std::move(peer->server));
        std::cerr << "node-opcua server (pid " << server_->pid() << ") at " << url_ << "\n";
    }

    static void TearDownTestSuite() {
        using namespace std::chrono_literals;
        if (server_) {
            const auto ended = server_->terminate(5s);
            std::cerr << "node-opcua server stopped: "
                      << (ended ? ended->describe() : ended.error()) << "\n";
            server_.reset();
        }
    }

    void SetUp() override {
        if (!unavailable_.empty()) {
            if (unavailableIsFailure_) {
                FAIL() << "SKILLCELL_REQUIRE_NODE=1 but " << unavailable_;
            }
            GTEST_SKIP() << "!!! node-opcua interop skipped: " << unavailable_ << " !!!";
        }
        ASSERT_TRUE(startError_.empty()) << startError_;
        ASSERT_TRUE(server_->running()) << "node-opcua server died";
    }

    /// True when SetUp() skipped or failed: a derived SetUp() returns then.
    [[nodiscard]] bool notReady() const { return IsSkipped() || HasFatalFailure() || HasFailure(); }
    [[nodiscard]] static const std::string& url() { return url_; }

private:
    static inline std::optional<process::ChildProcess> server_;
    static inline std::string url_;
    static inline std::string unavailable_;
    static inline bool unavailableIsFailure_ = false;
    static inline std::string startError_;
};

}  // namespace skillcell::test
