// `skillcell pki`: the operator's view of a component's PKI directory (ua/pki): list the
// certificates, trust a rejected peer, reject a trusted one, verify a certificate; create a cell
// CA, issue a component's certificate with it, revoke one. Output goes to stdout, errors to stderr;
// exit 0 on success, 1 when the operation fails, 2 on usage errors.
#include <CLI/CLI.hpp>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "common/atomic_file.hpp"
#include "ua/pki/certificate.hpp"
#include "ua/pki/certificate_authority.hpp"
#include "ua/pki/certificate_validator.hpp"
#include "ua/pki/file_util.hpp"
#include "ua/pki/own_certificate.hpp"
#include "ua/pki/trust_list.hpp"

namespace skillcell::apps {

namespace {

namespace fs = std::filesystem;
namespace pki = ua::pki;

struct PkiOptions {
    std::string pkiDir;
    std::string applicationUri = "urn:skillcell:server";
    std::string certificate;  // trust / reject / revoke: thumbprint, file name or path
    std::string caDir;
    std::string caName = "skillcell cell CA";
    int keyBits = 2048;
    int validDays = 7300;
    std::string uri;
    std::string commonName;
    std::vector<std::string> dnsNames;
    std::vector<std::string> ipAddresses;
    std::string hostName;  // verify
};

fs::path pkiDirectory(const PkiOptions& o) {
    return o.pkiDir.empty() ? pki::defaultPkiDirectory(o.applicationUri) : fs::path(o.pkiDir);
}

void addPkiDirOptions(CLI::App* cmd, PkiOptions& o) {
    cmd->add_option("--pki-dir", o.pkiDir,
                    "PKI directory (default: $SKILLCELL_PKI_DIR, else "
                    "~/.local/share/skillcell/pki/<application URI>, as the components use)");
    cmd->add_option("--application-uri", o.applicationUri,
                    "the component whose default PKI directory to use")
        ->capture_default_str();
}

std::string date(pki::Clock::time_point t) {
    const std::time_t tt = pki::Clock::to_time_t(t);
    std::tm tm{};
    gmtime_r(&tt, &tm);
    char buf[32] = {};
    std::strftime(buf, sizeof buf, "%Y-%m-%d", &tm);
    return buf;
}

void printSection(const std::string& title, const fs::path& dir) {
    const auto certs = pki::listCertificates(dir);
    std::cout << title << " (" << dir.string() << "): " << certs.size() << '\n';
    const auto now = pki::Clock::now();
    for (const auto& c : certs) {
        if (!c.info) {
            std::cout << "  " << c.file.filename().string() << "  UNREADABLE (not a certificate)\n";
            continue;
        }
        const auto& i = *c.info;
        const char* state = now > i.notAfter    ? "EXPIRED"
                            : now < i.notBefore ? "NOT YET VALID"
                                                : "valid";
        std::cout << "  " << i.thumbprint << "  " << c.file.filename().string() << '\n'
                  << "    subject  " << i.subject << (i.isCa ? "  [CA]" : "")
                  << (i.selfSigned ? "  [self-signed]" : "") << '\n';
        if (!i.selfSigned) std::cout << "    issuer   " << i.issuer << '\n';
        std::cout << "    uri      " << (i.applicationUri.empty() ? "-" : i.applicationUri) << '\n'
                  << "    key      "
                  << (i.keyType == "RSA" ? "RSA " + std::to_string(i.keyBits) + " bits" : i.keyType)
                  << '\n'
                  << "    validity " << date(i.notBefore) << " .. " << date(i.notAfter) << "  "
                  << state << '\n';
    }
}

int runList(const PkiOptions& o) {
    const pki::PkiPaths p{pkiDirectory(o)};
    std::error_code ec;
    if (!fs::is_directory(p.root, ec)) {
        std::cerr << "no PKI directory " << p.root.string()
                  << " (a component creates it on first start; or give --pki-dir)\n";
        return 1;
    }
    std::cout << "PKI directory " << p.root.string() << '\n';
    printSection("own", p.ownCerts());
    printSection("trusted", p.trustedCerts());
    printSection("issuers", p.issuersCerts());
    printSection("rejected", p.rejectedCerts());
    for (const auto& [title, dir] :
         {std::pair{"trusted crl", p.trustedCrl()}, std::pair{"issuers crl", p.issuersCrl()}}) {
        std::size_t n = 0;
        for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) ++n;
        std::cout << title << " (" << dir.string() << "): " << n << " file(s)\n";
    }
    return 0;
}

int runTrust(const PkiOptions& o) {
    const pki::PkiPaths p{pkiDirectory(o)};
    std::string error;
    std::error_code ec;
    // A path to a certificate file from elsewhere: copy it in, named by its thumbprint.
    if (fs::is_regular_file(o.certificate, ec) &&
        fs::absolute(o.certificate, ec).parent_path() != fs::absolute(p.rejectedCerts(), ec)) {
        auto certs = pki::readCertificateFile(o.certificate);
        if (certs.size() != 1) {
            std::cerr << o.certificate << " does not hold exactly one certificate\n";
            return 1;
        }
        const ua::ByteString der = pki::certificateDer(certs.front().get());
        const fs::path target = p.trustedCerts() / (pki::certificateThumbprintHex(der) + ".der");
        fs::create_directories(p.trustedCerts(), ec);
        if (!writeFileAtomically(
                target, {reinterpret_cast<const char*>(der.bytes.data()), der.bytes.size()},
                0644)) {
            std::cerr << "cannot write " << target.string() << '\n';
            return 1;
        }
        std::cout << "trusted " << target.string() << '\n';
        return 0;
    }
    const std::string wanted = fs::path(o.certificate).filename().string();
    auto found = pki::findCertificate(p.rejectedCerts(), wanted, &error);
    if (!found) {
        std::cerr << error << '\n';
        return 1;
    }
    auto moved = pki::moveCertificateFile(*found, p.trustedCerts(), &error);
    if (!moved) {
        std::cerr << error << '\n';
        return 1;
    }
    std::cout << "trusted " << moved->string() << '\n';
    return 0;
}

int runReject(const PkiOptions& o) {
    const pki::PkiPaths p{pkiDirectory(o)};
    std::string error;
    auto found = pki::findCertificate(p.trustedCerts(), o.certificate, &error);
    if (!found) {
        std::cerr << error << '\n';
        return 1;
    }
    auto moved = pki::moveCertificateFile(*found, p.rejectedCerts(), &error);
    if (!moved) {
        std::cerr << error << '\n';
        return 1;
    }
    std::cout << "rejected " << moved->string() << '\n';
    return 0;
}

int runInitCa(const PkiOptions& o) {
    pki::CaOptions options;
    options.name = o.caName;
    options.keyBits = o.keyBits;
    options.validDays = o.validDays;
    std::string error;
    auto ca = pki::createCertificateAuthority(o.caDir, options, &error);
    if (!ca) {
        std::cerr << "init-ca: " << error << '\n';
        return 1;
    }
    const auto info = pki::inspectCertificate(ca->certificate.get());
    std::cout << "created CA " << info.subject << "  thumbprint " << info.thumbprint << '\n'
              << "  certificate " << ca->certificateFile().string() << '\n'
              << "  private key " << ca->keyFile().string() << " (keep it secret)\n"
              << "  CRL         " << ca->crlFile().string() << '\n'
              << "Components use it when started with SKILLCELL_CA_DIR=" << ca->directory.string()
              << "\nor with a link <pki-dir>/cell-ca -> " << ca->directory.string()
              << "; or issue a certificate here with `skillcell pki issue`.\n";
    return 0;
}

int runIssue(const PkiOptions& o) {
    std::string error;
    auto ca = pki::loadCertificateAuthority(o.caDir, &error);
    if (!ca) {
        std::cerr << "issue: " << error << '\n';
        return 1;
    }
    pki::CertificateSubject subject;
    subject.applicationUri = o.uri;
    subject.commonName = o.commonName.empty() ? o.uri : o.commonName;
    subject.dnsNames = o.dnsNames;
    subject.ipAddresses = o.ipAddresses;
    const fs::path dir = o.pkiDir.empty() ? pki::defaultPkiDirectory(o.uri) : fs::path(o.pkiDir);
    auto own = pki::loadOrCreateOwnCertificate(dir, subject, &*ca, &error);
    if (!own) {
        std::cerr << "issue: " << error << '\n';
        return 1;
    }
    std::cout << (own->created ? "issued " : "kept (already issued by this CA) ")
              << own->certificateFile.string() << "  thumbprint "
              << pki::certificateThumbprintHex(own->der) << '\n';
    return 0;
}

int runRevoke(const PkiOptions& o) {
    std::string error;
    auto ca = pki::loadCertificateAuthority(o.caDir, &error);
    if (!ca) {
        std::cerr << "revoke: " << error << '\n';
        return 1;
    }
    std::error_code ec;
    if (!fs::is_regular_file(o.certificate, ec)) {
        std::cerr << "revoke: " << o.certificate << " is no certificate file\n";
        return 2;
    }
    const ua::ByteString der(pki::readWholeFile(o.certificate));
    if (const auto s = pki::revokeCertificate(*ca, der, &error); s.isBad()) {
        std::cerr << "revoke: " << error << '\n';
        return 1;
    }
    std::cout << "revoked " << pki::certificateThumbprintHex(der) << "; CRL "
              << ca->crlFile().string()
              << " (components pick it up on their next start; copy it into their trusted/crl "
                 "to apply it now)\n";
    return 0;
}

int runVerify(const PkiOptions& o) {
    const std::vector<std::uint8_t> bytes = pki::readWholeFile(o.certificate);
    if (bytes.empty()) {
        std::cerr << "verify: cannot read " << o.certificate << '\n';
        return 1;
    }
    // A PEM file is read as its certificates, concatenated as a peer would send them.
    ua::ByteString chain(bytes);
    if (auto certs = pki::readCertificateFile(o.certificate); !certs.empty()) {
        chain.bytes.clear();
        for (const auto& c : certs) {
            const ua::ByteString der = pki::certificateDer(c.get());
            chain.bytes.insert(chain.bytes.end(), der.bytes.begin(), der.bytes.end());
        }
    }
    pki::ValidatorOptions options;
    options.copyRejected = false;  // a dry run: only a peer's handshake fills rejected/
    pki::CertificateValidator validator(pkiDirectory(o), options);
    pki::PeerExpectations expected;
    expected.applicationUri = o.uri;
    expected.hostName = o.hostName;
    const auto verdict = validator.validate(chain, expected);
    std::cout << ua::statusName(verdict.status) << (verdict.ok() ? "" : ": ") << verdict.reason
              << '\n';
    return verdict.ok() ? 0 : 1;
}

}  // namespace

Command addPkiCommand(CLI::App& app) {
    auto o = std::make_shared<PkiOptions>();
    CLI::App* cmd = app.add_subcommand(
        "pki",
        "Manage a component's PKI directory (own/, trusted/, rejected/, issuers/): list "
        "certificates, trust or reject peers, and run a cell CA so that a cell's components "
        "trust each other.");
    cmd->require_subcommand(1);

    CLI::App* list = cmd->add_subcommand(
        "list",
        "List own, trusted, issuer and rejected certificates: thumbprint, subject, "
        "application URI, validity");
    addPkiDirOptions(list, *o);

    CLI::App* trust = cmd->add_subcommand(
        "trust",
        "Trust a peer: move its certificate from rejected/certs to trusted/certs "
        "(by thumbprint prefix or file name), or copy a certificate file into "
        "trusted/certs. Running components see it at their next handshake.");
    trust
        ->add_option("certificate", o->certificate,
                     "thumbprint (8+ hex digits), file name in rejected/certs, or a path")
        ->required();
    addPkiDirOptions(trust, *o);

    CLI::App* reject = cmd->add_subcommand(
        "reject", "Withdraw trust: move a certificate from trusted/certs to rejected/certs");
    reject
        ->add_option("certificate", o->certificate,
                     "thumbprint (8+ hex digits) or file name in trusted/certs")
        ->required();
    addPkiDirOptions(reject, *o);

    CLI::App* verify = cmd->add_subcommand(
        "verify",
        "Validate a certificate file (DER or PEM, a chain allowed) as a peer's "
        "certificate against the PKI directory, without copying it to rejected/; "
        "prints the status code and why. Exit 0 when it would be accepted, else 1.");
    verify->add_option("certificate", o->certificate, "the certificate file")->required();
    verify->add_option("--uri", o->uri, "the application URI it must name");
    verify->add_option("--host", o->hostName, "a host name or IP address it must name");
    addPkiDirOptions(verify, *o);

    CLI::App* initCa = cmd->add_subcommand(
        "init-ca",
        "Create a cell CA (RSA, SHA-256, CA:TRUE, keyCertSign/cRLSign) and its empty "
        "CRL in DIR. Refuses to overwrite an existing CA.");
    initCa->add_option("--dir", o->caDir, "directory for the CA")->required();
    initCa->add_option("--name", o->caName, "the CA's common name")->capture_default_str();
    initCa->add_option("--key-bits", o->keyBits, "RSA key size")
        ->check(CLI::IsMember({2048, 3072, 4096}))
        ->capture_default_str();
    initCa->add_option("--days", o->validDays, "validity in days")
        ->check(CLI::Range(1, 36500))
        ->capture_default_str();

    CLI::App* issue = cmd->add_subcommand(
        "issue",
        "Issue a component's application instance certificate with a cell CA into "
        "its PKI directory (own/), and trust the CA there; for components on hosts "
        "that must not hold the CA key.");
    issue->add_option("--ca", o->caDir, "the CA directory (from init-ca)")->required();
    issue->add_option("--uri", o->uri, "the component's application URI")->required();
    issue->add_option("--pki-dir", o->pkiDir,
                      "the component's PKI directory (default: as the component would use)");
    issue->add_option("--name", o->commonName, "common name (default: the URI)");
    issue->add_option("--dns", o->dnsNames, "host names for subjectAltName (repeatable)");
    issue->add_option("--ip", o->ipAddresses, "IP addresses for subjectAltName (repeatable)");

    CLI::App* revoke =
        cmd->add_subcommand("revoke", "Revoke a certificate the CA issued: add it to the CA's CRL");
    revoke->add_option("--ca", o->caDir, "the CA directory")->required();
    revoke->add_option("certificate", o->certificate, "the certificate file (DER or PEM)")
        ->required();

    return {cmd, [o, list, trust, reject, verify, initCa, issue, revoke] {
                if (list->parsed()) return runList(*o);
                if (trust->parsed()) return runTrust(*o);
                if (reject->parsed()) return runReject(*o);
                if (verify->parsed()) return runVerify(*o);
                if (initCa->parsed()) return runInitCa(*o);
                if (issue->parsed()) return runIssue(*o);
                if (revoke->parsed()) return runRevoke(*o);
                return 2;
            }};
}

}  // namespace skillcell::apps
