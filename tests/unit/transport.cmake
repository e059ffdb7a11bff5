# unit tests of src/ua/transport
skillcell_unit_test(test_transport transport_test.cpp)
target_link_libraries(test_transport PRIVATE skillcell_ua_transport)
target_include_directories(test_transport PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)

# Certificates made by the tests themselves (tests/support/test_certificate.hpp).
add_library(skillcell_test_certificates STATIC ${PROJECT_SOURCE_DIR}/tests/support/test_certificate.cpp)
target_include_directories(skillcell_test_certificates PUBLIC ${PROJECT_SOURCE_DIR}/tests/support)
target_link_libraries(skillcell_test_certificates PUBLIC skillcell_ua_crypto)

# The RSA security policies on a channel pair: every policy and mode, tampering, replay.
skillcell_unit_test(test_secure_channel_crypto secure_channel_crypto_test.cpp)
target_link_libraries(test_secure_channel_crypto PRIVATE skillcell_ua_transport skillcell_test_certificates)
