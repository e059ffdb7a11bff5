#pragma once
// The command-line side of a client's security: which endpoint to use, which certificate to
// show and which user to act for. Commands (`browse`, `skill`, `check`, `detect`) take
// --pki-dir, --security, --mode, --insecure and the user options; components take only the
// user options, prefixed --client- (their certificate is the server's, their trust list too).
//
// Passwords never appear on a command line, where `ps` shows them: they come from a file
// (first line) or from $SKILLCELL_PASSWORD.
#include <CLI/CLI.hpp>
#include <functional>
#include <optional>
#include <string>

#include "application_identity.hpp"
#include "ua/client/client.hpp"

namespace skillcell::apps {

struct ClientUserOptions {
    std::string name;                     // empty: anonymous
    std::string passwordFile;             // empty: $SKILLCELL_PASSWORD
    bool applicationCertificate = false;  // an X.509 user token: our own certificate
};

struct ClientSecurityOptions {
    std::string pkiDir;  // empty: ua::pki::defaultPkiDirectory(applicationUri)
    std::string applicationUri = "urn:skillcell:client";
    std::string policy = "best";  // best, or a policy name ("Basic256Sha256", ...)
    std::string mode = "SignAndEncrypt";
    bool insecure = false;  // SecurityPolicy None and no certificate at all
    ClientUserOptions user;
};

/// --user, --password-file, --user-certificate, each with `prefix` ("--client-").
void addClientUserOptions(CLI::App* cmd, ClientUserOptions& options, const std::string& prefix);
/// --pki-dir, --security, --mode, --insecure and the user options.
void addClientSecurityOptions(CLI::App* cmd, ClientSecurityOptions& options);

/// The client security of a component: the best secured endpoint with its identity, or
/// SecurityPolicy None when `insecure`. `error` says what is wrong.
[[nodiscard]] ua::Result<ua::ClientSecurity> componentClientSecurity(
    const ApplicationIdentity& identity, const ClientUserOptions& user, bool insecure,
    std::string* error);

/// The client security of a command. Sets `applicationUri` to the URI the certificate names
/// (an existing certificate in the PKI directory is used, never replaced).
[[nodiscard]] ua::Result<ua::ClientSecurity> commandClientSecurity(
    const ClientSecurityOptions& options, std::string* applicationUri, std::string* error);

/// The ClientConfig of a command with the security of `options`; nothing after printing
/// why on stderr.
[[nodiscard]] std::optional<ua::ClientConfig> commandClientConfig(
    const ClientSecurityOptions& options, const std::string& applicationName);

/// The body of a client command (`skill`, `run`): runs `body` with a client on a one-thread
/// io_context until it returns, and gives its exit code.
[[nodiscard]] int runClientCommand(const std::function<asio::awaitable<int>(ua::Client&)>& body);

/// Why a connection failed, with what to do about it when that is clear from the status.
[[nodiscard]] std::string explainConnectFailure(ua::StatusCode status);

/// "Aes256_Sha256_RsaPss/SignAndEncrypt", "None" for logs and command output.
[[nodiscard]] std::string describeSecurity(const std::string& policyUri,
                                           ua::MessageSecurityMode mode);

}  // namespace skillcell::apps
