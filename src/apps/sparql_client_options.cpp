#include "sparql_client_options.hpp"

namespace skillcell::apps {

http::ClientOptions sparqlClientOptions(const ua::ClientSecurity& security) {
    http::ClientOptions o;
    if (security.validateServerCertificate) {
        o.verifyServer = [check = security.validateServerCertificate](const ua::ByteString& der,
                                                                      std::string* reason) {
            return check(der, reason).isGood();
        };
    }
    const auto& user = security.user;
    switch (user.kind) {
        case ua::UserCredentials::Kind::UserName:
            o.auth = {http::ClientAuth::Kind::Basic, user.userName, user.password};
            break;
        case ua::UserCredentials::Kind::Certificate:
            o.certificate = user.certificate;
            o.privateKey = user.privateKey;
            break;
        case ua::UserCredentials::Kind::Anonymous:
            break;
    }
    return o;
}

}  // namespace skillcell::apps
