# unit tests of src/kb: Turtle, NodeSet2 -> OWL.
skillcell_unit_test(test_kb_owl kb/owl_test.cpp)
target_link_libraries(test_kb_owl PRIVATE skillcell_kb_owl)
