#pragma once
// Owning handles for the OpenSSL objects the crypto layer uses: each frees its object with
// the matching OpenSSL function, so no code path leaks one on an early return.
#include <openssl/evp.h>
#include <openssl/x509.h>

#include <memory>

namespace skillcell::ua::crypto {

template <class T, void (*Free)(T*)>
struct OpenSslDeleter {
    void operator()(T* p) const { Free(p); }
};

using PKeyHandle = std::unique_ptr<EVP_PKEY, OpenSslDeleter<EVP_PKEY, EVP_PKEY_free>>;
using PKeyCtxHandle =
    std::unique_ptr<EVP_PKEY_CTX, OpenSslDeleter<EVP_PKEY_CTX, EVP_PKEY_CTX_free>>;
using MdCtxHandle = std::unique_ptr<EVP_MD_CTX, OpenSslDeleter<EVP_MD_CTX, EVP_MD_CTX_free>>;
using CipherCtxHandle =
    std::unique_ptr<EVP_CIPHER_CTX, OpenSslDeleter<EVP_CIPHER_CTX, EVP_CIPHER_CTX_free>>;
using X509Handle = std::unique_ptr<X509, OpenSslDeleter<X509, X509_free>>;

}  // namespace skillcell::ua::crypto
