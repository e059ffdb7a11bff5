# src/kb: Turtle and NodeSet2 -> OWL; the SPARQL endpoint and store over HTTP(S) (src/http);
# a component's skills as RDF (src/kb/component_graph); Virtuoso and Konclude as child
# processes, against the real binaries (src/kb/engine); the knowledge base over them (src/kb).
skillcell_unit_test(test_kb SHARED_FIXTURE VirtuosoTest KnowledgeBaseTest
  kb/owl_test.cpp
  kb/https_test.cpp
  kb/component_graph_test.cpp
  kb/engine_test.cpp
  kb/knowledge_base_test.cpp)
target_link_libraries(test_kb PRIVATE skillcell_kb skillcell_kb_owl skillcell_http
                                      skillcell_kb_components skillcell_kb_engine skillcell_kb_rdf
                                      skillcell_mes skillcell_cell)
target_compile_definitions(test_kb PRIVATE SKILLCELL_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
target_include_directories(test_kb PRIVATE ${PROJECT_SOURCE_DIR}/tests/support)

# `skillcell nodeset2owl` on the command line: exit codes 2 (usage) and 1 (bad input), output.
add_test(NAME cli.nodeset2owl
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/kb/nodeset2owl_cli_test.sh $<TARGET_FILE:skillcell>
                 ${PROJECT_SOURCE_DIR}/models)
