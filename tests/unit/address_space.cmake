# unit tests of src/ua/address_space, src/ua/nodeset and the address-space service sets
skillcell_unit_test(test_address_space address_space_test.cpp)
target_link_libraries(test_address_space PRIVATE skillcell_ua_nodeset)

skillcell_unit_test(test_nodeset nodeset_test.cpp)
target_link_libraries(test_nodeset PRIVATE skillcell_ua_nodeset)
target_compile_definitions(test_nodeset PRIVATE
  SKILLCELL_MODELS_DIR="${PROJECT_SOURCE_DIR}/models")

skillcell_unit_test(test_services services_test.cpp)
target_link_libraries(test_services PRIVATE skillcell_ua_services)
