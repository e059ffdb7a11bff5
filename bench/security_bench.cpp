// skillcell_bench_security: what security costs. In one run, against our server in this
// process (loopback), for SecurityPolicy None and for each RSA policy with Sign and
// SignAndEncrypt:
//   - the handshake: connect (Hello, OpenSecureChannel, CreateSession, ActivateSession with
//     a user name and password), median and p99 over --connects runs;
//   - the Read round trip of one Double, median and p99 over --count sequential Reads.
// Prints a table with each row's ratio to None.
//
//   skillcell_bench_security [--count N] [--connects M]
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "latency_stats.hpp"
#include "running_server.hpp"
#include "test_certificate.hpp"
#include "ua/client/blocking_client.hpp"
#include "ua/crypto/security_policy_profile.hpp"
#include "ua/server/user_database.hpp"

namespace {

using namespace skillcell;
using Clock = std::chrono::steady_clock;

struct Row {
    std::string name;
    bench::LatencyStats connect;
    bench::LatencyStats read;
};

std::size_t parseCount(const char* text) {
    std::size_t v = 0;
    const auto* end = text + std::strlen(text);
    if (std::from_chars(text, end, v).ptr != end || v == 0) {
        std::cerr << "not a positive count: " << text << "\n";
        std::exit(2);
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t count = 5000;
    std::size_t connects = 30;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--count" && i + 1 < argc) {
            count = parseCount(argv[++i]);
        } else if (a == "--connects" && i + 1 < argc) {
            connects = parseCount(argv[++i]);
        } else {
            std::cerr << "usage: skillcell_bench_security [--count N] [--connects M]\n";
            return a == "--help" ? 0 : 2;
        }
    }
    spdlog::set_level(spdlog::level::warn);

    const auto serverCert = test::makeTestCertificate(2048, "urn:skillcell:server");
    const auto clientCert = test::makeTestCertificate(2048, "urn:skillcell:bench-client");
    ua::ServerConfig config = test::RunningServer::defaultConfig();
    config.description.certificate = serverCert.der;
    config.description.securityEndpoints = ua::allSecurityEndpoints(true);
    ua::UserTokenPolicy password;
    password.policyId = std::string(ua::kUserNamePolicyId);
    password.tokenType = ua::UserTokenType::UserName;
    config.description.userTokenPolicies = {password};
    config.security.privateKey = serverCert.key;
    config.security.allowAnonymous = false;
    auto users = std::make_shared<ua::UserDatabase>();
    if (users->setPassword("bench", ua::RoleSet{ua::Role::Operator}, "bench-pw").isBad()) return 1;
    config.security.users = users;
    test::RunningServer server(config);

    struct Variant {
        std::string name;
        std::string policy;
        ua::MessageSecurityMode mode;
    };
    std::vector<Variant> variants{
        {"None", std::string(ua::kSecurityPolicyNoneUri), ua::MessageSecurityMode::None}};
    for (const auto& p : ua::crypto::securityPolicyProfiles()) {
        variants.push_back({std::string(p.shortName) + " Sign", std::string(p.uri),
                            ua::MessageSecurityMode::Sign});
        variants.push_back({std::string(p.shortName) + " SignAndEncrypt", std::string(p.uri),
                            ua::MessageSecurityMode::SignAndEncrypt});
    }

    std::vector<Row> rows;
    for (const auto& v : variants) {
        ua::ClientConfig c;
        c.security.policyUri = v.policy;
        c.security.mode = v.mode;
        c.security.certificate = clientCert.der;
        c.security.privateKey = clientCert.key;
        c.serverCertificate = serverCert.der;  // as a client that knows the server would
        c.applicationUri = "urn:skillcell:bench-client";
        c.security.user.kind = ua::UserCredentials::Kind::UserName;
        c.security.user.userName = "bench";
        c.security.user.password = "bench-pw";
        Row row{v.name, {}, {}};
        bench::Samples connectTimes;
        for (std::size_t i = 0; i < connects; ++i) {
            ua::BlockingClient client;
            const auto t0 = Clock::now();
            const auto s = client.connect(server.url(), c);
            connectTimes.push_back(Clock::now() - t0);
            if (s.isBad()) {
                std::cerr << v.name << ": connect failed: " << ua::statusName(s) << "\n";
                return 1;
            }
        }
        row.connect = bench::summarize(std::move(connectTimes));
        ua::BlockingClient client;
        if (client.connect(server.url(), c).isBad()) return 1;
        bench::Samples readTimes;
        for (std::size_t i = 0; i < count + 100; ++i) {
            const auto t0 = Clock::now();
            auto value = client.readValue(ua::NodeId(2259));
            const auto t1 = Clock::now();
            if (!value) {
                std::cerr << v.name << ": read failed: " << ua::statusName(value.status()) << "\n";
                return 1;
            }
            if (i >= 100) readTimes.push_back(t1 - t0);  // the first 100 warm up
        }
        row.read = bench::summarize(std::move(readTimes));
        rows.push_back(std::move(row));
    }

    std::printf(
        "security cost on loopback (our client and server, one process); %zu reads, "
        "%zu connects per row\n\n",
        count, connects);
    std::printf("%-36s %12s %10s %8s %12s %10s %8s\n", "policy / mode", "connect med", "p99 (ms)",
                "x None", "read med", "p99 (us)", "x None");
    const auto& none = rows.front();
    for (const auto& r : rows) {
        std::printf("%-36s %12.2f %10.2f %8.2f %12.1f %10.1f %8.2f\n", r.name.c_str(),
                    r.connect.medianUs / 1000, r.connect.p99Us / 1000,
                    r.connect.medianUs / none.connect.medianUs, r.read.medianUs, r.read.p99Us,
                    r.read.medianUs / none.read.medianUs);
    }
    return 0;
}
