# The skill layer: the state machine table, skills served by a component, the SkillClient and
# SkillConnection (two skills over one session), the example of a new skill type
# (examples/dispense_skill), the conformance checker (`skillcell check`, docs/conformance.md)
# against servers holding conforming and broken skills, and the SkillDetector and
# RemoteSkillBrowser against skill servers on loopback (no multicast: the tests feed the
# detector's "appeared"/"gone" themselves). The "tsan" preset
# runs the detector's tests under ThreadSanitizer:
# cmake --preset tsan && cmake --build --preset tsan && ctest --preset tsan.
skillcell_unit_test(test_skills
  skill_state_machine_test.cpp
  skill_test.cpp
  skill_client_test.cpp
  skill_connection_test.cpp
  example_dispense_test.cpp
  conformance_checker_test.cpp
  skill_detector_test.cpp)
target_include_directories(test_skills PRIVATE ${PROJECT_SOURCE_DIR}/examples/dispense_skill)
find_package(nlohmann_json REQUIRED)
target_link_libraries(test_skills PRIVATE skillcell_skills skillcell_test_support
                                          nlohmann_json::nlohmann_json)
target_compile_definitions(test_skills PRIVATE
  # One test starts a real `skillcell server` process and kills it mid-run.
  SKILLCELL_BINARY="$<TARGET_FILE:skillcell>"
  SKILLCELL_EXAMPLE_MODEL="${PROJECT_SOURCE_DIR}/examples/dispense_skill/Example.DispenseSkill.NodeSet2.xml")
add_dependencies(test_skills skillcell)

# The command as a device maker runs it, against `skillcell server --noop-skill`: output and
# exit codes (0 passed, 1 failed, 2 usage or connection error).
add_test(NAME cli.check_vs_noop_skill
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/check_command_vs_noop_skill.sh $<TARGET_FILE:skillcell>)
set_tests_properties(cli.check_vs_noop_skill PROPERTIES TIMEOUT 120)
