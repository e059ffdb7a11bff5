// skillcell_bench_security: what security costs. In one run, against our server in this
// process (loopback), for SecurityPolicy None and for each RSA policy with Sign and
// SignAndEncrypt, with RSA 2048 keys:
//   - the handshake: connect (Hello, OpenSecureChannel, CreateSession, ActivateSession with
//     a user name and password), median and p99 over --connects runs, and the CPU time the
//     process (client and server together) spent per connect;
//   - the Read round trip of one Double, median and p99 over --count sequential Reads.
// Then, for the policy components use (Aes256_Sha256_RsaPss, SignAndEncrypt), the user token
// (password: an scrypt hash on the server; X.509: one more RSA signature and verification)
// and the key size (RSA 2048 and 3072, server and client); and ECC_nistP256 and ECC_nistP384
// with P-256 and P-384 keys, whose users are X.509 certificates (no password travels over ECC
// here).
// Prints a table with each row's ratio to None.
//
//   skillcell_bench_security [--count N] [--connects M] [--only TEXT]
// --only runs the rows whose name contains TEXT, e.g. to profile one; ratios are then to the
// first of them.
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include "common/command_line.hpp"
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
    double cpuPerConnectMs = 0;
    bench::LatencyStats read;
};

/// User and system CPU of this process (client and server), in ms.
double processCpuMs() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const auto ms = [](const timeval& t) {
        return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_usec) / 1e3;
    };
    return ms(usage.ru_utime) + ms(usage.ru_stime);
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t count = 5000;
    std::size_t connects = 30;
    std::string only;
    CLI::App app{
        "What security costs: the handshake and the Read round trip for each policy and "
        "mode, the user token and the key size, against our server in this process"};
    app.add_option("--count", count, "Reads per row (round trip)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--connects", connects, "connects per row (handshake)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--only", only,
                   "run only the rows whose name contains this text (ratios are then to the "
                   "first of them)");
    if (const auto exit = skillcell::parseCommandLine(app, argc, argv)) return *exit;
    spdlog::set_level(spdlog::level::warn);

    // One server per key (RSA 2048, RSA 3072, P-256, P-384), each knowing the bench's user by
    // password and by certificate.
    struct Keys {
        test::TestCertificate server;
        test::TestCertificate client;
    };
    std::vector<Keys> keys;
    for (int bits : {2048, 3072}) {
        keys.push_back({test::makeTestCertificate(bits, "urn:skillcell:server"),
                        test::makeTestCertificate(bits, "urn:skillcell:bench-client")});
    }
    constexpr std::size_t kEccKeys = 2;  // then one per curve, in the profiles' order
    for (const auto& p : ua::crypto::securityPolicyProfiles()) {
        if (!p.isEcc()) continue;
        keys.push_back({test::makeTestEccCertificate(p.keyKind, "urn:skillcell:server"),
                        test::makeTestEccCertificate(p.keyKind, "urn:skillcell:bench-client")});
    }
    std::vector<std::unique_ptr<test::RunningServer>> servers;
    for (const auto& k : keys) {
        ua::ServerConfig config = test::RunningServer::defaultConfig();
        config.description.certificate = k.server.der;
        config.description.securityEndpoints =
            ua::allSecurityEndpoints(true, {k.server.key.kind()});
        ua::UserTokenPolicy password;
        password.policyId = std::string(ua::kUserNamePolicyId);
        password.tokenType = ua::UserTokenType::UserName;
        ua::UserTokenPolicy x509;
        x509.policyId = std::string(ua::kCertificatePolicyId);
        x509.tokenType = ua::UserTokenType::Certificate;
        config.description.userTokenPolicies = {password, x509};
        config.security.privateKey = k.server.key;
        config.security.allowAnonymous = false;
        auto users = std::make_shared<ua::UserDatabase>();
        if (users->setPassword("bench", ua::RoleSet{ua::Role::Operator}, "bench-pw").isBad() ||
            users->setCertificate("bench-cert", ua::RoleSet{ua::Role::Operator}, k.client.der)
                .isBad()) {
            return 1;
        }
        config.security.users = users;
        servers.push_back(std::make_unique<test::RunningServer>(config));
    }

    struct Variant {
        std::string name;
        std::string policy;
        ua::MessageSecurityMode mode;
        std::size_t keys = 0;  // index into keys
        bool x509User = false;
    };
    std::vector<Variant> variants{
        {"None", std::string(ua::kSecurityPolicyNoneUri), ua::MessageSecurityMode::None}};
    for (const auto& p : ua::crypto::securityPolicyProfiles()) {
        if (p.isEcc()) continue;
        variants.push_back({std::string(p.shortName) + " Sign", std::string(p.uri),
                            ua::MessageSecurityMode::Sign});
        variants.push_back({std::string(p.shortName) + " SignAndEncrypt", std::string(p.uri),
                            ua::MessageSecurityMode::SignAndEncrypt});
    }
    const auto* best = ua::crypto::findSecurityPolicyProfileByName("Aes256_Sha256_RsaPss");
    if (best == nullptr) return 1;
    const std::string bestName = std::string(best->shortName) + " S&E";
    variants.push_back({bestName + ", X.509 user", std::string(best->uri),
                        ua::MessageSecurityMode::SignAndEncrypt, 0, true});
    variants.push_back({bestName + ", RSA 3072", std::string(best->uri),
                        ua::MessageSecurityMode::SignAndEncrypt, 1, false});
    variants.push_back({bestName + ", RSA 3072, X.509 user", std::string(best->uri),
                        ua::MessageSecurityMode::SignAndEncrypt, 1, true});
    std::size_t eccKeys = kEccKeys;
    for (const auto& p : ua::crypto::securityPolicyProfiles()) {
        if (!p.isEcc()) continue;
        variants.push_back({std::string(p.shortName) + " Sign, X.509 user", std::string(p.uri),
                            ua::MessageSecurityMode::Sign, eccKeys, true});
        variants.push_back({std::string(p.shortName) + " S&E, X.509 user", std::string(p.uri),
                            ua::MessageSecurityMode::SignAndEncrypt, eccKeys, true});
        ++eccKeys;
    }

    std::vector<Row> rows;
    for (const auto& v : variants) {
        if (!only.empty() && v.name.find(only) == std::string::npos) continue;
        const auto& k = keys[v.keys];
        const auto& server = *servers[v.keys];
        ua::ClientConfig c;
        c.security.policyUri = v.policy;
        c.security.mode = v.mode;
        c.security.certificate = k.client.der;
        c.security.privateKey = k.client.key;
        c.serverCertificate = k.server.der;  // as a client that knows the server would
        c.applicationUri = "urn:skillcell:bench-client";
        if (v.x509User) {
            c.security.user.kind = ua::UserCredentials::Kind::Certificate;
            c.security.user.certificate = k.client.der;
            c.security.user.privateKey = k.client.key;
        } else {
            c.security.user.kind = ua::UserCredentials::Kind::UserName;
            c.security.user.userName = "bench";
            c.security.user.password = "bench-pw";
        }
        Row row{v.name, {}, 0, {}};
        bench::Samples connectTimes;
        const double cpuBefore = processCpuMs();
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
        row.cpuPerConnectMs = (processCpuMs() - cpuBefore) / static_cast<double>(connects);
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

    if (rows.empty()) {
        std::cerr << "no row's name contains \"" << only << "\"\n";
        return 2;
    }
    std::printf(
        "security cost on loopback (our client and server, one process; RSA 2048 and a "
        "user with a password unless the row says otherwise); %zu reads, %zu connects per row; "
        "cpu: both ends' CPU per connect\n\n",
        count, connects);
    std::printf("%-48s %12s %10s %8s %9s %12s %10s %8s\n", "policy / mode", "connect med",
                "p99 (ms)", "x first", "cpu (ms)", "read med", "p99 (us)", "x first");
    const auto& none = rows.front();  // None, unless --only left it out
    for (const auto& r : rows) {
        std::printf("%-48s %12.2f %10.2f %8.2f %9.2f %12.1f %10.1f %8.2f\n", r.name.c_str(),
                    r.connect.medianUs / 1000, r.connect.p99Us / 1000,
                    r.connect.medianUs / none.connect.medianUs, r.cpuPerConnectMs, r.read.medianUs,
                    r.read.p99Us, r.read.medianUs / none.read.medianUs);
    }
    return 0;
}
