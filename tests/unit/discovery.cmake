# Discovery: the DNS wire format, the mDNS service cache and the LDS logic and services
# (no multicast needed), then the mDNS responder, watcher and registrar on real multicast,
# each test case in a private network namespace of its own (tests/netns/run_in_private_netns.sh
# as the test "emulator"), so that nothing reaches a real network.
skillcell_unit_test(test_dns dns_message_test.cpp service_cache_test.cpp)
target_link_libraries(test_dns PRIVATE skillcell_ua_dns)

skillcell_unit_test(test_lds lds_test.cpp)
target_link_libraries(test_lds PRIVATE skillcell_ua_discovery skillcell_test_support)

add_executable(test_mdns mdns_test.cpp)
target_link_libraries(test_mdns PRIVATE skillcell_ua_discovery skillcell_test_support
                                        GTest::gtest_main)
set_target_properties(test_mdns PROPERTIES
  CROSSCOMPILING_EMULATOR ${PROJECT_SOURCE_DIR}/tests/netns/run_in_private_netns.sh)
gtest_discover_tests(test_mdns DISCOVERY_TIMEOUT 30 PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 60)
