# unit tests of src/ua/client
skillcell_unit_test(test_client client_test.cpp)
target_link_libraries(test_client PRIVATE skillcell_ua_client)
skillcell_unit_test(test_client_subscription client_subscription_test.cpp)
target_link_libraries(test_client_subscription PRIVATE skillcell_ua_client)

# Our client against our server with every security policy, users and roles.
skillcell_unit_test(test_client_security client_security_test.cpp)
target_link_libraries(test_client_security PRIVATE skillcell_ua_client skillcell_test_support
  skillcell_test_certificates)

# The refusals of security end to end: real PKI directory, a man in the middle, logs.
skillcell_unit_test(test_security_refusals security_refusals_test.cpp)
target_link_libraries(test_security_refusals PRIVATE skillcell_ua_client skillcell_test_support
  skillcell_test_certificates skillcell_pki_test_support spdlog::spdlog)
