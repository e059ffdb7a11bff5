#include "client_security_options.hpp"

#include <asio/co_spawn.hpp>
#include <asio/detached.hpp>
#include <asio/io_context.hpp>

#include <cstdlib>
#include <fstream>
#include <iostream>

#include "ua/types/to_string.hpp"

#include "ua/crypto/security_policy_profile.hpp"

namespace skillcell::apps {

void addClientUserOptions(CLI::App* cmd, ClientUserOptions& o, const std::string& prefix) {
    cmd->add_option(prefix + "user", o.name,
                    "user name to open sessions as (default: anonymous); the password comes "
                    "from " +
                        prefix + "password-file or $SKILLCELL_PASSWORD");
    cmd->add_option(prefix + "password-file", o.passwordFile,
                    "file whose first line is the password of " + prefix + "user")
        ->check(CLI::ExistingFile);
    cmd->add_flag(prefix + "user-certificate", o.applicationCertificate,
                  "authenticate with the application certificate as an X.509 user token "
                  "(the server maps it to a user with `skillcell user add --certificate`)");
}

void addClientSecurityOptions(CLI::App* cmd, ClientSecurityOptions& o) {
    cmd->add_option("--pki-dir", o.pkiDir,
                    "our PKI directory: certificate (created on first use), trusted/ servers, "
                    "rejected/ (default: $SKILLCELL_PKI_DIR, else "
                    "~/.local/share/skillcell/pki/urn_skillcell_client)");
    cmd->add_option("--security", o.policy,
                    "best (the most secure endpoint the server offers), or Basic256Sha256, "
                    "Aes128_Sha256_RsaOaep, Aes256_Sha256_RsaPss, ECC_nistP256, ECC_nistP384 "
                    "(the ECC ones need a certificate with a key on that curve)")
        ->capture_default_str();
    cmd->add_option("--mode", o.mode, "with an explicit --security: Sign or SignAndEncrypt")
        ->check(CLI::IsMember({"Sign", "SignAndEncrypt"}))
        ->capture_default_str();
    cmd->add_flag("--insecure", o.insecure,
                  "development only: SecurityPolicy None, for servers run with --insecure");
    addClientUserOptions(cmd, o.user, "--");
}

namespace {

/// The client is the application: its certificates (the P-256 one, under a cell CA, for
/// ECC_nistP256 where the server offers it) and its trust list.
void actAs(const ApplicationIdentity& identity, ua::ClientSecurity& security) {
    security.certificate = identity.certificate().der;
    security.privateKey = identity.privateKey();
    security.eccCertificate = identity.eccCertificate().der;
    security.eccPrivateKey = identity.eccPrivateKey();
    security.validateServerCertificate = identity.serverCertificateCheck();
}

ua::Result<std::string> readPassword(const ClientUserOptions& user, const std::string& prefix,
                                     std::string* error) {
    std::string password;
    if (!user.passwordFile.empty()) {
        std::ifstream in(user.passwordFile);
        if (!in || !std::getline(in, password)) {
            *error = "cannot read a password from " + user.passwordFile;
            return ua::status::BadConfigurationError;
        }
        if (!password.empty() && password.back() == '\r') password.pop_back();
    } else if (const char* env = std::getenv("SKILLCELL_PASSWORD"); env != nullptr) {
        password = env;
    }
    if (password.empty()) {
        *error = prefix + "user " + user.name + " needs a password: " + prefix +
                 "password-file FILE or $SKILLCELL_PASSWORD";
        return ua::status::BadConfigurationError;
    }
    return password;
}

ua::StatusCode fillUser(const ApplicationIdentity* identity, const ClientUserOptions& user,
                        const std::string& prefix, ua::UserCredentials& credentials,
                        std::string* error) {
    if (user.applicationCertificate && !user.name.empty()) {
        *error = prefix + "user and " + prefix + "user-certificate exclude each other";
        return ua::status::BadConfigurationError;
    }
    if (user.applicationCertificate) {
        if (identity == nullptr) {
            *error = prefix + "user-certificate needs security (not --insecure)";
            return ua::status::BadConfigurationError;
        }
        credentials.kind = ua::UserCredentials::Kind::Certificate;
        credentials.certificate = identity->certificate().der;
        credentials.privateKey = identity->privateKey();
        return ua::status::Good;
    }
    if (user.name.empty()) return ua::status::Good;  // anonymous
    auto password = readPassword(user, prefix, error);
    if (!password) return password.status();
    credentials.kind = ua::UserCredentials::Kind::UserName;
    credentials.userName = user.name;
    credentials.password = std::move(*password);
    return ua::status::Good;
}

}  // namespace

ua::Result<ua::ClientSecurity> componentClientSecurity(const ApplicationIdentity& identity,
                                                       const ClientUserOptions& user, bool insecure,
                                                       std::string* error) {
    ua::ClientSecurity security;
    if (!insecure) {
        security.policyUri = std::string(ua::kBestSecurity);
        actAs(identity, security);
    }
    if (const auto s =
            fillUser(insecure ? nullptr : &identity, user, "--client-", security.user, error);
        s.isBad()) {
        return s;
    }
    return security;
}

ua::Result<ua::ClientSecurity> commandClientSecurity(const ClientSecurityOptions& options,
                                                     std::string* applicationUri,
                                                     std::string* error) {
    *applicationUri = options.applicationUri;
    ua::ClientSecurity security;
    if (options.insecure) {
        if (const auto s = fillUser(nullptr, options.user, "--", security.user, error); s.isBad()) {
            return s;
        }
        return security;
    }
    if (options.policy == "best") {
        security.policyUri = std::string(ua::kBestSecurity);
    } else if (const auto* profile = ua::crypto::findSecurityPolicyProfileByName(options.policy)) {
        security.policyUri = std::string(profile->uri);
        security.mode = options.mode == "Sign" ? ua::MessageSecurityMode::Sign
                                               : ua::MessageSecurityMode::SignAndEncrypt;
    } else {
        *error = "unknown --security '" + options.policy +
                 "' (best, Basic256Sha256, Aes128_Sha256_RsaOaep, Aes256_Sha256_RsaPss, "
                 "ECC_nistP256 or ECC_nistP384)";
        return ua::status::BadConfigurationError;
    }
    const std::filesystem::path pkiDir = options.pkiDir.empty()
                                             ? ua::pki::defaultPkiDirectory(options.applicationUri)
                                             : std::filesystem::path(options.pkiDir);
    // A PKI directory shared with a component ($SKILLCELL_PKI_DIR) holds the component's
    // certificate: act as that application rather than replace its certificate.
    std::ifstream existing(pkiDir / "own/certs/cert.der", std::ios::binary);
    if (existing) {
        ua::ByteString der(std::vector<std::uint8_t>(std::istreambuf_iterator<char>(existing), {}));
        if (auto uri = ua::pki::certificateApplicationUri(der); !uri.empty()) {
            *applicationUri = uri;
        }
    }
    auto identity = ApplicationIdentity::load(pkiDir, *applicationUri, "skillcell", error);
    if (!identity) return identity.status();
    actAs(*identity, security);
    if (const auto s = fillUser(&*identity, options.user, "--", security.user, error); s.isBad()) {
        return s;
    }
    return security;
}

std::optional<ua::ClientConfig> commandClientConfig(const ClientSecurityOptions& options,
                                                    const std::string& applicationName) {
    ua::ClientConfig config;
    std::string error;
    auto security = commandClientSecurity(options, &config.applicationUri, &error);
    if (!security) {
        std::cerr << error << "\n";
        return std::nullopt;
    }
    config.security = std::move(*security);
    config.applicationName = applicationName;
    config.sessionName = applicationName;
    return config;
}

std::string explainConnectFailure(ua::StatusCode status) {
    std::string text(ua::statusName(status));
    if (status == ua::status::BadSecurityPolicyRejected) {
        text +=
            " (no endpoint of the server has a security we accept; a server run with "
            "--insecure needs --insecure here too)";
    } else if (status == ua::status::BadCertificateUntrusted ||
               status == ua::status::BadSecurityChecksFailed) {
        text +=
            " (a certificate is not trusted: `skillcell pki list` on either side shows "
            "the rejected one, `skillcell pki trust` accepts it)";
    } else if (status == ua::status::BadIdentityTokenRejected ||
               status == ua::status::BadIdentityTokenInvalid ||
               status == ua::status::BadUserAccessDenied) {
        text += " (the server refused the user: --user and a password, or a user it knows)";
    }
    return text;
}

std::string describeSecurity(const std::string& policyUri, ua::MessageSecurityMode mode) {
    const auto* profile = ua::crypto::findSecurityPolicyProfile(policyUri);
    if (profile == nullptr) return "None";
    return std::string(profile->shortName) +
           (mode == ua::MessageSecurityMode::Sign ? "/Sign" : "/SignAndEncrypt");
}

int runClientCommand(const std::function<asio::awaitable<int>(ua::Client&)>& body) {
    asio::io_context io{1};
    ua::Client client(io.get_executor());
    int code = 1;
    asio::co_spawn(
        io, [&]() -> asio::awaitable<void> { code = co_await body(client); }, asio::detached);
    io.run();
    return code;
}

}  // namespace skillcell::apps
