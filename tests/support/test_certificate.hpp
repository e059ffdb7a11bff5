#pragma once
// Certificates made on the spot for tests: an RSA (or P-256) key and a self-signed X.509
// certificate with the application URI in its subjectAltName, valid from `validFrom` to `validTo`
// (seconds relative to now). No files are committed; the keys are kept in the build
// directory for the test processes after the first (test_certificate.cpp says why).
#include <string>

#include "ua/crypto/primitives.hpp"
#include "ua/types/builtin.hpp"

namespace skillcell::test {

struct TestCertificate {
    ua::ByteString der;
    ua::crypto::AsymmetricKey key;
};

[[nodiscard]] TestCertificate makeTestCertificate(int bits, const std::string& applicationUri,
                                                  long validFrom = -3600,
                                                  long validTo = 3600L * 24 * 365);
/// The same with a fresh NIST P-256 key (ECDSA-signed), for the ECC policies.
[[nodiscard]] TestCertificate makeTestEccCertificate(const std::string& applicationUri,
                                                     long validFrom = -3600,
                                                     long validTo = 3600L * 24 * 365);
/// A year's certificate with a fresh key on the curve `curve` names (P-256 or P-384).
[[nodiscard]] TestCertificate makeTestEccCertificate(ua::crypto::AsymmetricKey::Kind curve,
                                                     const std::string& applicationUri);

}  // namespace skillcell::test
