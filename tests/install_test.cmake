# The installation, end to end: cmake --install BUILD_DIR into a fresh prefix, then the installed
# rabbit from an empty folder outside any checkout, with no RABBIT_DATA: it finds the installed
# data (the data root's last rule), lists the shipped gaits, and `rabbit run` writes its report
# below the working directory. Run as cmake -DBUILD_DIR=... -P install_test.cmake.
if(NOT BUILD_DIR)
  message(FATAL_ERROR "install_test: give -DBUILD_DIR=<the build folder>")
endif()
set(tmp "$ENV{TMPDIR}")
if(NOT tmp)
  set(tmp "/tmp")
endif()
string(RANDOM LENGTH 8 tag)
set(root "${tmp}/rabbit_install_test_${tag}")
set(prefix "${root}/prefix")
set(empty "${root}/empty")
file(REMOVE_RECURSE "${root}")
file(MAKE_DIRECTORY "${empty}")

function(check_run what)
  cmake_parse_arguments(ARG "" "EXPECT" "COMMAND" ${ARGN})
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=RABBIT_DATA ${ARG_COMMAND}
                  WORKING_DIRECTORY "${empty}" RESULT_VARIABLE code OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    file(REMOVE_RECURSE "${root}")
    message(FATAL_ERROR "${what}: exit ${code}\n${out}\n${err}")
  endif()
  if(ARG_EXPECT AND NOT out MATCHES "${ARG_EXPECT}")
    file(REMOVE_RECURSE "${root}")
    message(FATAL_ERROR "${what}: the output does not match '${ARG_EXPECT}':\n${out}\n${err}")
  endif()
  message(STATUS "${what}: ok")
endfunction()

execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}"
                RESULT_VARIABLE code OUTPUT_QUIET ERROR_VARIABLE err)
if(NOT code EQUAL 0)
  file(REMOVE_RECURSE "${root}")
  message(FATAL_ERROR "cmake --install failed (${code}): ${err}")
endif()
foreach(file bin/rabbit share/rabbit-gait/gaits/reference/index.csv
             share/rabbit-gait/gaits/gait_pattern.fll share/rabbit-gait/gaits/networks/index.csv
             share/rabbit-gait/scenarios/paper.toml
             share/rabbit-gait/optimizers/jobs/velocity_gains.toml)
  if(NOT EXISTS "${prefix}/${file}")
    file(REMOVE_RECURSE "${root}")
    message(FATAL_ERROR "cmake --install did not install ${file}")
  endif()
endforeach()

set(rabbit "${prefix}/bin/rabbit")
check_run("rabbit --version" COMMAND "${rabbit}" --version
          EXPECT "data root: ${prefix}/share/rabbit-gait \\(found by: install prefix\\)")
check_run("rabbit gaits list" COMMAND "${rabbit}" gaits list EXPECT "vm_0.60 ")
check_run("rabbit run" COMMAND "${rabbit}" run --filter "^flat$" -j 2 --no-html
          EXPECT "verdict    PASSED")
if(NOT EXISTS "${empty}/reports/paper/summary.csv")
  file(REMOVE_RECURSE "${root}")
  message(FATAL_ERROR "the installed rabbit run wrote no ${empty}/reports/paper/summary.csv")
endif()
file(REMOVE_RECURSE "${root}")
