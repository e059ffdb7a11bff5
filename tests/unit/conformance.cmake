# The conformance checker (`skillcell check`, docs/conformance.md) against in-process
# servers holding conforming and broken skills.
skillcell_unit_test(test_conformance_checker conformance_checker_test.cpp)
target_link_libraries(test_conformance_checker PRIVATE skillcell_skills skillcell_test_support)
