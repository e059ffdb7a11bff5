# Test support shared by the server-level tests: a server on a thread, a raw TCP client.
add_library(skillcell_test_support STATIC
  ${PROJECT_SOURCE_DIR}/tests/support/running_server.cpp
  ${PROJECT_SOURCE_DIR}/tests/support/raw_connection.cpp
  ${PROJECT_SOURCE_DIR}/tests/support/tampering_proxy.cpp
  ${PROJECT_SOURCE_DIR}/tests/support/socket_io.cpp
  ${PROJECT_SOURCE_DIR}/tests/support/test_nodes.cpp)
target_include_directories(skillcell_test_support PUBLIC ${PROJECT_SOURCE_DIR}/tests/support)
target_link_libraries(skillcell_test_support PUBLIC skillcell_ua_server)

skillcell_unit_test(test_server server_protocol_test.cpp session_test.cpp client_server_test.cpp)
target_link_libraries(test_server PRIVATE skillcell_test_support skillcell_ua_client)
