# proprio_warnings(target): the project's warning set; -Werror unless sanitizing (GCC advises
# against combining the two).
function(proprio_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wshadow)
  if(PROPRIO_WERROR AND NOT PROPRIO_SANITIZE AND NOT PROPRIO_FUZZ)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# The libFuzzer build (make fuzz, clang only): every source instrumented for coverage and checked by
# ASan/UBSan; the fuzz_* programs link libFuzzer's main (tests/fuzz).
if(PROPRIO_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
elseif(PROPRIO_SANITIZE)
  # -g1: line tables only, enough for the sanitizers' file:line reports. Full debug info made the
  # sanitizer tree 14 GB per clone (CI ran out of disk at the link, session 35).
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
                      -g1)
  add_link_options(-fsanitize=address,undefined)
endif()

# proprio_module(name SOURCES ... PUBLIC_DEPS ... PRIVATE_DEPS ...): one library per module,
# exported as proprio::<name>.
function(proprio_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(proprio_${name} ${ARG_SOURCES})
  add_library(proprio::${name} ALIAS proprio_${name})
  set_target_properties(proprio_${name} PROPERTIES EXPORT_NAME ${name} OUTPUT_NAME proprio_${name})
  target_include_directories(proprio_${name}
    PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
           $<BUILD_INTERFACE:${PROJECT_BINARY_DIR}/generated>
           $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(proprio_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  proprio_warnings(proprio_${name})
  install(TARGETS proprio_${name} EXPORT proprioTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
endfunction()

# proprio_test(name SOURCES ... LIBS ... [LABELS ...]): a GoogleTest program registered with ctest.
function(proprio_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  # Paths relative to the test program (tests/support/paths.hpp), never absolute ones of the tree:
  # the compile lines stay the same in every clone, so ccache serves a fresh clone elsewhere.
  file(RELATIVE_PATH source_from_bin ${CMAKE_CURRENT_BINARY_DIR} ${PROJECT_SOURCE_DIR})
  file(RELATIVE_PATH cli_from_bin ${CMAKE_CURRENT_BINARY_DIR} ${PROJECT_BINARY_DIR}/app/proprio)
  if(source_from_bin STREQUAL "")
    set(source_from_bin ".")
  endif()
  target_compile_definitions(${name} PRIVATE
    PROPRIO_OPENCV_SAMPLES="${PROPRIO_OPENCV_SAMPLES}"
    PROPRIO_TEST_SOURCE_FROM_BIN="${source_from_bin}"
    PROPRIO_TEST_CLI_FROM_BIN="${cli_from_bin}")
  proprio_warnings(${name})
  # Tests read the source tree's data/, never an installed copy.
  set(labels "")
  if(ARG_LABELS)
    set(labels LABELS ${ARG_LABELS})
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES TIMEOUT 600 ENVIRONMENT "PROPRIO_DATA_DIR=${PROJECT_SOURCE_DIR}/data"
                                  ${labels})
endfunction()
