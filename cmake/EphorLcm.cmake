# Generates C++ headers (and, with a JDK, a jar for lcm-spy) from
# lcmtypes/*.lcm with lcm-gen at build time. LCM 1.3.1 has no CMake support.

function(ephor_lcm_types target)
  cmake_parse_arguments(ARG "" "" "TYPES" ${ARGN})
  set(cpp_dir ${CMAKE_BINARY_DIR}/lcmtypes/cpp)
  set(headers "")
  foreach(lcm_file ${ARG_TYPES})
    get_filename_component(stem ${lcm_file} NAME_WE)
    list(APPEND headers ${cpp_dir}/ephor/${stem}.hpp)
  endforeach()
  add_custom_command(
    OUTPUT ${headers}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${cpp_dir}
    COMMAND ${LCM_GEN} --cpp --cpp-hpath ${cpp_dir} ${ARG_TYPES}
    # Decoders refuse array counts beyond the message's bytes (issue 18).
    COMMAND sed -i -E -f ${CMAKE_SOURCE_DIR}/cmake/lcm_bound_counts.sed ${headers}
    DEPENDS ${ARG_TYPES} ${CMAKE_SOURCE_DIR}/cmake/lcm_bound_counts.sed
    WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
    COMMENT "lcm-gen: C++ types"
    VERBATIM)
  add_custom_target(${target}_gen DEPENDS ${headers})
  add_library(${target} INTERFACE)
  add_dependencies(${target} ${target}_gen)
  target_include_directories(${target} SYSTEM INTERFACE ${cpp_dir})
  target_link_libraries(${target} INTERFACE PkgConfig::LCM)

  # A jar of the same types so lcm-spy can decode them (tools/ephor spy).
  if(Java_FOUND AND EXISTS /usr/share/java/lcm.jar)
    include(UseJava)
    set(java_dir ${CMAKE_BINARY_DIR}/lcmtypes/java)
    set(jar ${CMAKE_BINARY_DIR}/lcmtypes/ephor_types.jar)
    add_custom_command(
      OUTPUT ${jar}
      COMMAND ${CMAKE_COMMAND} -E rm -rf ${java_dir}
      COMMAND ${CMAKE_COMMAND} -E make_directory ${java_dir}/classes
      COMMAND ${LCM_GEN} --java --jpath ${java_dir}/src ${ARG_TYPES}
      COMMAND sh -c "${Java_JAVAC_EXECUTABLE} -nowarn -cp /usr/share/java/lcm.jar -d ${java_dir}/classes $(find ${java_dir}/src -name '*.java')"
      COMMAND ${Java_JAR_EXECUTABLE} cf ${jar} -C ${java_dir}/classes .
      DEPENDS ${ARG_TYPES}
      WORKING_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}
      COMMENT "lcm-gen: Java types jar for lcm-spy"
      VERBATIM)
    add_custom_target(${target}_jar ALL DEPENDS ${jar})
  endif()
endfunction()
