# postinstall_fortran: installs the build tree into a temporary prefix and
# builds a Fortran program against the installed module and libraries, three
# ways: plain compiler flags, pkg-config, CMake find_package. Runs each.
#   cmake -DBUILD_DIR= -DPREFIX= -DWORK_DIR= -DFC= -DMODDIR= -DLIBDIR=
#         -DPKG_CONFIG= -DCMAKE_EXE= -DSOURCE_DIR= -P postinstall.cmake
cmake_minimum_required(VERSION 3.18)
set(passed 0)
set(failed 0)
macro(result ok what)
  if(${ok})
    math(EXPR passed "${passed} + 1")
    message(STATUS "ok    ${what}")
  else()
    math(EXPR failed "${failed} + 1")
    message(STATUS "FAIL  ${what}")
  endif()
endmacro()
# runs a command; ok_var is TRUE when it exits with 0
function(run ok_var)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    set(${ok_var} TRUE PARENT_SCOPE)
  else()
    set(${ok_var} FALSE PARENT_SCOPE)
    message(STATUS "command failed (${rc}): ${ARGN}\n${out}${err}")
  endif()
  set(${ok_var}_OUT "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${PREFIX} ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
run(installed ${CMAKE_EXE} --install ${BUILD_DIR} --prefix ${PREFIX})
result(installed "cmake --install ${BUILD_DIR} --prefix ${PREFIX}")
foreach(f ${MODDIR}/nitschedyn.mod ${LIBDIR}/libnitschedyn_fortran.so ${LIBDIR}/libnitschedyn.so
        ${LIBDIR}/pkgconfig/nitschedyn-fortran.pc ${LIBDIR}/cmake/nitschedyn_fortran/nitschedyn_fortran-config.cmake)
  if(EXISTS ${PREFIX}/${f})
    result(TRUE "installed ${f}")
  else()
    result(FALSE "installed ${f}")
  endif()
endforeach()
set(env ${CMAKE_EXE} -E env LD_LIBRARY_PATH=${PREFIX}/${LIBDIR})

# runs a consumer and checks that it loads the installed libraries
macro(check_consumer exe how)
  run(ran ${env} ${exe})
  result(ran "the consumer built with ${how} runs")
  message(STATUS "${ran_OUT}")
  run(ldd ${env} ldd ${exe})
  string(FIND "${ldd_OUT}" "${PREFIX}/${LIBDIR}/libnitschedyn_fortran.so" at)
  if(at GREATER -1)
    result(TRUE "it loads ${PREFIX}/${LIBDIR}/libnitschedyn_fortran.so")
  else()
    result(FALSE "it loads ${PREFIX}/${LIBDIR}/libnitschedyn_fortran.so:\n${ldd_OUT}")
  endif()
endmacro()

# 1. plain flags: gfortran -I<prefix>/include/... prog.f90 -L<prefix>/lib -lnitschedyn_fortran -lnitschedyn
run(built ${FC} -I${PREFIX}/${MODDIR} ${SOURCE_DIR}/consumer.f90 -o ${WORK_DIR}/consumer_flags
    -L${PREFIX}/${LIBDIR} -lnitschedyn_fortran -lnitschedyn)
result(built "${FC} -I${PREFIX}/${MODDIR} consumer.f90 -L${PREFIX}/${LIBDIR} -lnitschedyn_fortran -lnitschedyn")
if(built)
  check_consumer(${WORK_DIR}/consumer_flags "plain flags")
endif()

# 2. pkg-config (the .pc file finds the prefix relative to itself)
if(PKG_CONFIG)
  run(pc ${CMAKE_EXE} -E env PKG_CONFIG_PATH=${PREFIX}/${LIBDIR}/pkgconfig
      ${PKG_CONFIG} --cflags --libs nitschedyn-fortran)
  result(pc "pkg-config --cflags --libs nitschedyn-fortran")
  if(pc)
    string(STRIP "${pc_OUT}" flags)
    separate_arguments(flags UNIX_COMMAND "${flags}")
    run(built ${FC} ${SOURCE_DIR}/consumer.f90 -o ${WORK_DIR}/consumer_pc ${flags})
    result(built "${FC} consumer.f90 $(pkg-config --cflags --libs nitschedyn-fortran)")
    if(built)
      check_consumer(${WORK_DIR}/consumer_pc "pkg-config")
    endif()
  endif()
else()
  message(STATUS "pkg-config not found: skipping that way")
endif()

# 3. CMake: find_package(nitschedyn_fortran) and nitschedyn::nitschedyn_fortran
run(configured ${CMAKE_EXE} -S ${SOURCE_DIR} -B ${WORK_DIR}/cmake -DCMAKE_Fortran_COMPILER=${FC}
    -DCMAKE_PREFIX_PATH=${PREFIX})
result(configured "find_package(nitschedyn_fortran) with CMAKE_PREFIX_PATH=${PREFIX}")
if(configured)
  run(built ${CMAKE_EXE} --build ${WORK_DIR}/cmake)
  result(built "the consumer builds with CMake")
  if(built)
    check_consumer(${WORK_DIR}/cmake/consumer "CMake")
  endif()
endif()

message(STATUS "${passed} passed, ${failed} failed")
if(failed GREATER 0)
  message(FATAL_ERROR "postinstall_fortran failed")
endif()
