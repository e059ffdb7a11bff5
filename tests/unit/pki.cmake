# ua/pki: certificates, trust lists, validation, the cell CA; and `skillcell pki`.
add_library(skillcell_pki_test_support STATIC pki_test_support.cpp)
target_link_libraries(skillcell_pki_test_support PUBLIC skillcell_ua_pki)

# Not skillcell_unit_test(): the "pki." prefix lets `ctest -R pki` select exactly these.
add_executable(test_pki pki_validator_test.cpp pki_certificate_test.cpp pki_ca_test.cpp)
target_link_libraries(test_pki PRIVATE skillcell_pki_test_support skillcell_ua_crypto
                               GTest::gtest_main GTest::gmock)
gtest_discover_tests(test_pki TEST_PREFIX "pki." DISCOVERY_TIMEOUT 30)

# The operator's view: `skillcell pki` init-ca, list, trust, reject, issue; exit codes.
add_test(NAME cli.pki COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/pki_cli_test.sh $<TARGET_FILE:skillcell>)
set_tests_properties(cli.pki PROPERTIES TIMEOUT 120)
