# unit tests of src/ua/transport
skillcell_unit_test(test_transport transport_test.cpp)
target_link_libraries(test_transport PRIVATE skillcell_ua_transport)
