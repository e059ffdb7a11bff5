# Discovery: the DNS wire format, the mDNS service cache and the LDS logic and services
# (no multicast needed). The mDNS responder, watcher and registrar on real multicast are
# tested in a private network namespace (namespaces.cmake).
skillcell_unit_test(test_discovery dns_message_test.cpp service_cache_test.cpp lds_test.cpp
                    response_planner_test.cpp link_states_test.cpp)
target_link_libraries(test_discovery PRIVATE skillcell_ua_dns skillcell_ua_discovery
                                             skillcell_test_support)
