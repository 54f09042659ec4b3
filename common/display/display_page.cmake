# ephor_display_page(NAME NAMESPACE ns FILES /abs/index.html /abs/page.js ...)
# A static library holding a display page's files, embedded at build time by
# embed_assets.cmake, each served at "/" + its file name, found with
#   const ephor::display::WebAsset* <ns>::find_web_asset(std::string_view path)
# (declare it in the page's own header). Every system's display includes
# this file: include(${CMAKE_SOURCE_DIR}/common/display/display_page.cmake).
# The shared page script and style (web/ephor_page.js, web/ephor_page.css
# here) are in EPHOR_DISPLAY_SHARED_WEB_FILES for pages built on them.
set(EPHOR_DISPLAY_DIR ${CMAKE_CURRENT_LIST_DIR})
set(EPHOR_DISPLAY_SHARED_WEB_FILES ${CMAKE_CURRENT_LIST_DIR}/web/ephor_page.js
                                   ${CMAKE_CURRENT_LIST_DIR}/web/ephor_page.css)

function(ephor_display_page name)
  cmake_parse_arguments(ARG "" "NAMESPACE" "FILES" ${ARGN})
  set(out ${CMAKE_CURRENT_BINARY_DIR}/${name}_assets.cc)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out} -DNAMESPACE=${ARG_NAMESPACE} "-DFILES=${ARG_FILES}"
            -P ${EPHOR_DISPLAY_DIR}/embed_assets.cmake
    DEPENDS ${ARG_FILES} ${EPHOR_DISPLAY_DIR}/embed_assets.cmake
    COMMENT "embedding the page ${name}"
    VERBATIM)
  ephor_library(${name} SOURCES ${out} DEPS)
endfunction()
