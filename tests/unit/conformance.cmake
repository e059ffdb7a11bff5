# The conformance checker (`skillcell check`, docs/conformance.md) against in-process
# servers holding conforming and broken skills.
skillcell_unit_test(test_conformance_checker conformance_checker_test.cpp)
target_link_libraries(test_conformance_checker PRIVATE skillcell_skills skillcell_test_support)

# The command as a device maker runs it, against `skillcell server --noop-skill`: output and
# exit codes (0 passed, 1 failed, 2 usage or connection error).
add_test(NAME cli.check_vs_noop_skill
         COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/check_command_vs_noop_skill.sh $<TARGET_FILE:skillcell>)
set_tests_properties(cli.check_vs_noop_skill PROPERTIES TIMEOUT 120)
