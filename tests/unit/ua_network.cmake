# Test support shared by the tests below and by the device, skill and MES tests:
# certificates made by the tests themselves (tests/support/test_certificate.hpp), a server on
# a thread, a raw TCP client, a tampering proxy.
add_library(skillcell_test_certificates STATIC ${PROJECT_SOURCE_DIR}/tests/support/test_certificate.cpp)
target_include_directories(skillcell_test_certificates PUBLIC ${PROJECT_SOURCE_DIR}/tests/support)
target_link_libraries(skillcell_test_certificates PUBLIC skillcell_ua_crypto)
# Where the tests keep the RSA keys they made, for the test processes after them.
target_compile_definitions(skillcell_test_certificates PRIVATE
  SKILLCELL_TEST_KEY_DIR="${CMAKE_BINARY_DIR}/test-keys")

add_library(skillcell_test_support STATIC
  ${PROJECT_SOURCE_DIR}/tests/support/running_server.cpp
  ${PROJECT_SOURCE_DIR}/tests/support/raw_connection.cpp
  ${PROJECT_SOURCE_DIR}/tests/support/tampering_proxy.cpp
  ${PROJECT_SOURCE_DIR}/tests/support/socket_io.cpp
  ${PROJECT_SOURCE_DIR}/tests/support/test_nodes.cpp)
target_include_directories(skillcell_test_support PUBLIC ${PROJECT_SOURCE_DIR}/tests/support)
target_link_libraries(skillcell_test_support PUBLIC skillcell_ua_server skillcell_process)

# OPC UA over the network: framing and the transport; the RSA security policies on a
# channel pair (every policy and mode, tampering, replay); the server's protocol and
# sessions; the client; subscriptions, both the clock-free core (fake time) and the services
# over real sockets; and the server's refusals by role.
skillcell_unit_test(test_ua_network
  transport_test.cpp
  secure_channel_crypto_test.cpp
  server_protocol_test.cpp
  session_test.cpp
  client_server_test.cpp
  client_test.cpp
  client_subscription_test.cpp
  client_security_test.cpp
  security_refusals_test.cpp
  subscription_core_test.cpp
  subscription_socket_test.cpp)
target_link_libraries(test_ua_network PRIVATE
  skillcell_ua_transport skillcell_ua_client skillcell_ua_subscriptions skillcell_test_support
  skillcell_test_certificates skillcell_pki_test_support)
