# unit tests of src/kb: Turtle, NodeSet2 -> OWL.
skillcell_unit_test(test_kb_owl kb/owl_test.cpp)
target_link_libraries(test_kb_owl PRIVATE skillcell_kb_owl)
target_compile_definitions(test_kb_owl PRIVATE SKILLCELL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

# HTTP/1.1 messages, client and server (src/kb/http).
skillcell_unit_test(test_kb_http kb/http_test.cpp)
target_link_libraries(test_kb_http PRIVATE skillcell_kb_http)

# Virtuoso and Konclude as child processes, against the real binaries (src/kb/engine).
skillcell_unit_test(test_kb_engine SHARED_FIXTURE VirtuosoTest kb/engine_test.cpp)
target_link_libraries(test_kb_engine PRIVATE skillcell_kb_engine skillcell_kb_rdf)

# The knowledge base over a real Virtuoso and Konclude (src/kb).
skillcell_unit_test(test_kb SHARED_FIXTURE KnowledgeBaseTest kb/knowledge_base_test.cpp)
target_link_libraries(test_kb PRIVATE skillcell_kb)

# `skillcell kb` in a cell: discovery-driven loading of a component's skills.
skillcell_cell_test(test_kb_component kb/kb_component_test.cpp)
target_link_libraries(test_kb_component PRIVATE skillcell_kb_http)
target_compile_definitions(test_kb_component PRIVATE SKILLCELL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

# A component's skills as RDF (src/kb/component_graph).
skillcell_unit_test(test_kb_component_graph kb/component_graph_test.cpp)
target_link_libraries(test_kb_component_graph PRIVATE skillcell_kb_components)

# `skillcell nodeset2owl` on the command line: exit codes 2 (usage) and 1 (bad input), output.
add_test(NAME cli.nodeset2owl
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/kb/nodeset2owl_cli_test.sh $<TARGET_FILE:skillcell>
                 ${PROJECT_SOURCE_DIR}/models)
