// `skillcell user`: the users a component accepts (ua/server/user_database.hpp). Passwords
// are read from stdin (one line), never from the command line where `ps` would show them,
// and stored only as scrypt hashes. Exit 0 on success, 1 when the operation fails, 2 on
// usage errors.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>

#include "commands.hpp"
#include "ua/pki/own_certificate.hpp"
#include "ua/server/user_database.hpp"

namespace skillcell::apps {
namespace {

namespace fs = std::filesystem;

struct UserOptions {
    std::string usersFile;
    std::string pkiDir;
    std::string applicationUri = "urn:skillcell:server";
    std::string name;
    std::vector<std::string> roles;
    std::vector<std::string> certificateFiles;
};

fs::path usersFile(const UserOptions& o) {
    if (!o.usersFile.empty()) return o.usersFile;
    const fs::path pki =
        o.pkiDir.empty() ? ua::pki::defaultPkiDirectory(o.applicationUri) : fs::path(o.pkiDir);
    return pki / "users";
}

void addFileOptions(CLI::App* cmd, UserOptions& o) {
    cmd->add_option("--users", o.usersFile, "user database (default: <pki-dir>/users)");
    cmd->add_option("--pki-dir", o.pkiDir,
                    "the component's PKI directory, whose users file to use (default: "
                    "$SKILLCELL_PKI_DIR, else ~/.local/share/skillcell/pki/<application URI>)");
    cmd->add_option("--application-uri", o.applicationUri,
                    "the component whose default PKI directory to use")
        ->capture_default_str();
}

int add(const UserOptions& o) {
    ua::RoleSet roles;
    for (const auto& r : o.roles) {
        const auto role = ua::parseRole(r);
        if (!role) {
            std::cerr << "unknown role '" << r << "' (Observer, Operator, Engineer, Admin)\n";
            return 2;
        }
        roles.add(*role);
    }
    const fs::path file = usersFile(o);
    std::string error;
    auto db = ua::UserDatabase::load(file, &error);
    if (!db) {
        std::cerr << error << "\n";
        return 1;
    }
    ua::StatusCode s = ua::status::Good;
    if (!o.certificateFiles.empty()) {
        std::vector<ua::ByteString> certificates;
        for (const auto& certificateFile : o.certificateFiles) {
            std::ifstream in(certificateFile, std::ios::binary);
            if (!in) {
                std::cerr << "cannot read " << certificateFile << "\n";
                return 1;
            }
            certificates.emplace_back(
                std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {}));
        }
        s = db->setCertificates(o.name, roles, certificates);
    } else {
        std::string password;
        if (!std::getline(std::cin, password) || password.empty()) {
            std::cerr << "give the password on stdin (one line), e.g. "
                         "`printf '%s\\n' \"$PASSWORD\" | skillcell user add ...`\n";
            return 2;
        }
        s = db->setPassword(o.name, roles, password);
    }
    if (s.isBad()) {
        std::cerr << "cannot add '" << o.name << "': " << ua::statusName(s)
                  << " (names without ':' or spaces, at least one role; a DER certificate)\n";
        return s == ua::status::BadInvalidArgument ? 2 : 1;
    }
    fs::create_directories(file.parent_path());
    if (db->save(file, &error).isBad()) {
        std::cerr << error << "\n";
        return 1;
    }
    std::cout << "user " << o.name << " (" << roles.toString() << ") in " << file.string() << "\n";
    return 0;
}

int list(const UserOptions& o) {
    std::string error;
    auto db = ua::UserDatabase::load(usersFile(o), &error);
    if (!db) {
        std::cerr << error << "\n";
        return 1;
    }
    for (const auto& u : db->users()) {
        const auto kind = u.credential.substr(0, u.credential.find('$'));
        // An application's certificates each have a line: the thumbprint tells them apart.
        std::cout << u.name << "\t" << u.roles.toString() << "\t"
                  << (kind == "x509" ? "certificate " + u.credential.substr(5) : "password")
                  << "\n";
    }
    return 0;
}

int remove(const UserOptions& o) {
    const fs::path file = usersFile(o);
    std::string error;
    auto db = ua::UserDatabase::load(file, &error);
    if (!db) {
        std::cerr << error << "\n";
        return 1;
    }
    if (!db->remove(o.name)) {
        std::cerr << "no user '" << o.name << "' in " << file.string() << "\n";
        return 1;
    }
    if (db->save(file, &error).isBad()) {
        std::cerr << error << "\n";
        return 1;
    }
    return 0;
}

}  // namespace

Command addUserCommand(CLI::App& app) {
    auto* cmd = app.add_subcommand(
        "user", "manage the users a component accepts (user name + password, or certificate)");
    cmd->require_subcommand(1);
    auto o = std::make_shared<UserOptions>();

    auto* addCmd = cmd->add_subcommand(
        "add", "add or replace a user; the password is read from stdin (one line)");
    addCmd->add_option("name", o->name, "user name")->required();
    addCmd->add_option("--role", o->roles, "Observer, Operator, Engineer or Admin (repeatable)")
        ->required()
        ->delimiter(',');
    addCmd->add_option("--certificate", o->certificateFiles,
                       "identify the user by this X.509 certificate (DER) instead of a password; "
                       "repeat it for each certificate of an application (own/certs/cert.der and, "
                       "under a cell CA, cert-nistP256.der, which it uses over ECC_nistP256)");
    addFileOptions(addCmd, *o);
    auto* listCmd = cmd->add_subcommand("list", "list the users and their roles");
    addFileOptions(listCmd, *o);
    auto* removeCmd = cmd->add_subcommand("remove", "remove a user");
    removeCmd->add_option("name", o->name, "user name")->required();
    addFileOptions(removeCmd, *o);

    return {cmd, [o, addCmd, listCmd] {
                if (*addCmd) return add(*o);
                if (*listCmd) return list(*o);
                return remove(*o);
            }};
}

}  // namespace skillcell::apps
