# Tests of the manual pages, the installation and the ABI, and the target that
# records the ABI baseline. Included once, after the library target exists
# (from tests/CMakeLists.txt or the top-level CMakeLists.txt); uses absolute
# paths only, so it does not matter which directory includes it.
#
#   man_pages              tests/man_pages.sh: lint, a page or alias for every
#                          function and exported symbol, synopses = header,
#                          ERRORS codes are real, examples compile and run
#   abi_guard              tests/abi_guard.sh check against abi/nitschedyn.abi
#   postinstall_pkgconfig, postinstall_cmake, postinstall_man
#                          tests/postinstall (install into a fresh prefix, use it)
#   target abi-update      rewrite abi/nitschedyn.abi from the current build
enable_testing()

# (the page examples are compiled as plain programs: not in a sanitizer build)
if(NOT ND_SANITIZE)
  add_test(NAME man_pages
    COMMAND sh ${PROJECT_SOURCE_DIR}/tests/man_pages.sh ${PROJECT_SOURCE_DIR}
            $<TARGET_FILE:nitschedyn> ${CMAKE_C_COMPILER} ${PROJECT_BINARY_DIR}/tests/man_pages)
  set_tests_properties(man_pages PROPERTIES LABELS man)
endif()

add_test(NAME abi_guard
  COMMAND sh ${PROJECT_SOURCE_DIR}/tests/abi_guard.sh check ${CMAKE_C_COMPILER}
          ${PROJECT_SOURCE_DIR}/include/nitschedyn.h $<TARGET_FILE:nitschedyn>
          ${PROJECT_SOURCE_DIR}/abi/nitschedyn.abi ${PROJECT_BINARY_DIR}/tests/abi_guard)
set_tests_properties(abi_guard PROPERTIES LABELS abi)

if(NOT TARGET abi-update)
  add_custom_target(abi-update
    COMMAND sh ${PROJECT_SOURCE_DIR}/tests/abi_guard.sh update ${CMAKE_C_COMPILER}
            ${PROJECT_SOURCE_DIR}/include/nitschedyn.h $<TARGET_FILE:nitschedyn>
            ${PROJECT_SOURCE_DIR}/abi/nitschedyn.abi ${PROJECT_BINARY_DIR}/tests/abi_update
    DEPENDS nitschedyn
    COMMENT "Recording the ABI baseline abi/nitschedyn.abi"
    VERBATIM)
endif()

# (not in a sanitizer build: consumers would link an ASan library without ASan)
if(NOT ND_SANITIZE)
  add_subdirectory(${PROJECT_SOURCE_DIR}/tests/postinstall ${PROJECT_BINARY_DIR}/tests/postinstall)
endif()
