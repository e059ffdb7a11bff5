# unit tests of src/ua/client
skillcell_unit_test(test_client client_test.cpp)
target_link_libraries(test_client PRIVATE skillcell_ua_client)
