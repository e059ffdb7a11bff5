# The address space and what fills it: the binary encoding, nodes and references, NodeSet2
# loading and writing, instantiation of types, dynamic structures, and the skill models as
# NodeSets.
skillcell_unit_test(test_ua_nodes
  encoding_test.cpp
  address_space_test.cpp
  nodeset_test.cpp
  instantiate_test.cpp
  dynamic_structure_test.cpp
  nodeset_roundtrip_test.cpp
  skill_models_test.cpp)
target_link_libraries(test_ua_nodes PRIVATE skillcell_ua_encoding skillcell_ua_nodeset
                                            skillcell_ua_services skillcell_ua_server)
target_compile_definitions(test_ua_nodes PRIVATE SKILLCELL_MODELS_DIR="${PROJECT_SOURCE_DIR}/models")

# The attribute, view and method services on an address space, without a server: the file
# stands in for the server's Session, so it cannot share an executable with the server.
skillcell_unit_test(test_services services_test.cpp)
target_link_libraries(test_services PRIVATE skillcell_ua_services)
