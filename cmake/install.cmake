# Install rules of the C library: the shared library (versioned, with its
# SONAME and development symlinks), the header, the manual pages with one
# alias per extra function name (and section 1), the driver bin/nitschedyn, the pkg-config file nitschedyn.pc and the
# CMake package nitschedyn (target nitschedyn::nitschedyn).
# `make install PREFIX=...` runs `cmake --install build --prefix ...`: both
# install exactly these files.
include(CMakePackageConfigHelpers)

set(ND_CMAKE_PACKAGE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/nitschedyn)

# --- library and header
# (the target's INSTALL_INTERFACE include directory goes into the export)
install(TARGETS nitschedyn EXPORT nitschedynTargets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES ${PROJECT_SOURCE_DIR}/include/nitschedyn.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
if(ND_WITH_PETSC)  # nd_problem_set_comm, exported by these builds only
  install(FILES ${PROJECT_SOURCE_DIR}/include/nitschedyn_mpi.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()

# --- manual pages: man/*.3, and for every further name in the NAME section
#     of a page (.Nm) a page that is only `.so man3/<page>.3`, so that
#     `man nd_mesh_destroy` finds nd_mesh_create(3). tests/man_pages.sh checks
#     that these names cover the header and the exported symbols.
file(GLOB ND_MAN3 CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/man/*.3)
list(SORT ND_MAN3)
set(ND_MAN_ALIAS_DIR ${PROJECT_BINARY_DIR}/man-aliases)
set(ND_MAN_ALIASES)
set(ND_MAN_ALIAS_FILES)
foreach(page IN LISTS ND_MAN3)
  get_filename_component(page_name ${page} NAME)
  string(REGEX REPLACE "\\.3$" "" page_name "${page_name}")
  set_property(DIRECTORY ${PROJECT_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${page})
  file(STRINGS ${page} page_lines REGEX "^\\.(Sh|Nm)( |$)")
  set(in_name FALSE)
  foreach(line IN LISTS page_lines)
    if(line MATCHES "^\\.Sh ")
      if(line STREQUAL ".Sh NAME")
        set(in_name TRUE)
      else()
        set(in_name FALSE)
      endif()
    elseif(in_name AND line MATCHES "^\\.Nm ([A-Za-z0-9_]+)")
      set(alias ${CMAKE_MATCH_1})
      if(NOT alias STREQUAL page_name AND NOT EXISTS ${PROJECT_SOURCE_DIR}/man/${alias}.3
         AND NOT alias IN_LIST ND_MAN_ALIASES)
        list(APPEND ND_MAN_ALIASES ${alias})
        file(CONFIGURE OUTPUT ${ND_MAN_ALIAS_DIR}/${alias}.3 CONTENT ".so man3/${page_name}.3\n")
        list(APPEND ND_MAN_ALIAS_FILES ${ND_MAN_ALIAS_DIR}/${alias}.3)
      endif()
    endif()
  endforeach()
endforeach()
install(FILES ${ND_MAN3} ${ND_MAN_ALIAS_FILES} DESTINATION ${CMAKE_INSTALL_MANDIR}/man3)
# section 1: the command-line driver nitschedyn(1)
file(GLOB ND_MAN1 CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/man/*.1)
install(FILES ${ND_MAN1} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)

# --- the command-line driver (tools/cli), found through its rpath $ORIGIN/../lib
if(TARGET nitschedyn_cli)
  install(TARGETS nitschedyn_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()

# --- pkg-config: nitschedyn.pc from cmake/nitschedyn.pc.in. The prefix is
#     found relative to the file (${pcfiledir}), so that an installed tree,
#     whatever --prefix it was installed with, may be moved. Libs.private
#     lists what libnitschedyn.so itself links, taken from the target's link
#     libraries at the end of the configuration (so that libraries added
#     later in CMakeLists.txt, such as SuiteSparse's, are included).
function(nd_pkgconfig_flags_of item out_var)
  set(flags)
  if(item MATCHES "^\\$<")                     # generator expression: not for pkg-config
  elseif(TARGET ${item})
    get_target_property(imported ${item} IMPORTED)
    get_target_property(type ${item} TYPE)
    set(location)
    if(imported AND NOT type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(location ${item} IMPORTED_LOCATION)
      if(NOT location)
        get_target_property(configs ${item} IMPORTED_CONFIGURATIONS)
        if(configs)
          list(GET configs 0 config)
          get_target_property(location ${item} IMPORTED_LOCATION_${config})
        endif()
      endif()
    endif()
    if(location)
      nd_pkgconfig_flags_of("${location}" flags)
    endif()
    if(imported OR type STREQUAL "STATIC_LIBRARY" OR type STREQUAL "INTERFACE_LIBRARY")
      get_target_property(deps ${item} INTERFACE_LINK_LIBRARIES)
      if(deps)
        foreach(dep IN LISTS deps)
          nd_pkgconfig_flags_of("${dep}" dep_flags)
          list(APPEND flags ${dep_flags})
        endforeach()
      endif()
    endif()
  elseif(item MATCHES "^-")                    # -lfoo, -pthread, ...
    set(flags "${item}")
  elseif(IS_ABSOLUTE "${item}")                # /usr/lib/x86_64-linux-gnu/liblapacke.so
    get_filename_component(dir "${item}" DIRECTORY)
    get_filename_component(file "${item}" NAME)
    if(file MATCHES "^lib(.+)\\.(so|a|dylib)(\\..*)?$")
      if(NOT dir IN_LIST CMAKE_C_IMPLICIT_LINK_DIRECTORIES
         AND NOT dir IN_LIST CMAKE_CXX_IMPLICIT_LINK_DIRECTORIES)
        list(APPEND flags "-L${dir}")
      endif()
      list(APPEND flags "-l${CMAKE_MATCH_1}")
    else()
      set(flags "${item}")
    endif()
  elseif(item MATCHES "^[A-Za-z0-9_.+-]+$")    # m, pthread, ...
    set(flags "-l${item}")
  endif()
  set(${out_var} ${flags} PARENT_SCOPE)
endfunction()

function(nd_write_pkgconfig)
  get_target_property(link_libs nitschedyn LINK_LIBRARIES)
  set(private)
  if(link_libs)
    foreach(item IN LISTS link_libs)
      nd_pkgconfig_flags_of("${item}" item_flags)
      list(APPEND private ${item_flags})
    endforeach()
  endif()
  list(APPEND private -lstdc++ -lm)            # the library is C++ inside
  list(REMOVE_DUPLICATES private)
  string(REPLACE ";" " " ND_PC_LIBS_PRIVATE "${private}")
  file(RELATIVE_PATH ND_PC_TO_PREFIX "/prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/prefix")
  string(REGEX REPLACE "/$" "" ND_PC_TO_PREFIX "${ND_PC_TO_PREFIX}")
  configure_file(${PROJECT_SOURCE_DIR}/cmake/nitschedyn.pc.in ${PROJECT_BINARY_DIR}/nitschedyn.pc @ONLY)
endfunction()
if(CMAKE_VERSION VERSION_GREATER_EQUAL 3.19)
  cmake_language(DEFER DIRECTORY ${PROJECT_SOURCE_DIR} CALL nd_write_pkgconfig)
else()
  nd_write_pkgconfig()
endif()
install(FILES ${PROJECT_BINARY_DIR}/nitschedyn.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# --- CMake package: find_package(nitschedyn) gives nitschedyn::nitschedyn
install(EXPORT nitschedynTargets NAMESPACE nitschedyn::
  DESTINATION ${ND_CMAKE_PACKAGE_DIR} FILE nitschedynTargets.cmake)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/nitschedynConfig.cmake.in
  ${PROJECT_BINARY_DIR}/nitschedynConfig.cmake
  INSTALL_DESTINATION ${ND_CMAKE_PACKAGE_DIR}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR CMAKE_INSTALL_MANDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/nitschedynConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/nitschedynConfig.cmake
              ${PROJECT_BINARY_DIR}/nitschedynConfigVersion.cmake
  DESTINATION ${ND_CMAKE_PACKAGE_DIR})
