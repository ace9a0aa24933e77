# Programs of the public C API (samples/, tools/): each links the shared library only and may
# read the headers in harness/. Included by the CMakeLists that add them.
include_guard(GLOBAL)

# pbf_add_program(NAME SOURCES... [LIBS LIBRARIES...]): the executable, with -Wall -Wextra on
# GCC and Clang.
function(pbf_add_program name)
  cmake_parse_arguments(arg "" "" "LIBS" ${ARGN})
  add_executable(${name} ${arg_UNPARSED_ARGUMENTS})
  target_link_libraries(${name} PRIVATE pbf ${arg_LIBS})
  target_include_directories(${name} PRIVATE ${PROJECT_SOURCE_DIR}/harness)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${name} PRIVATE -Wall -Wextra)
  endif()
endfunction()

# pbf_add_cli_tool(NAME WHERE SOURCES...): a program whose arguments CLI11 parses, a requirement
# of the tools only; without CLI11 (Debian libcli11-dev) NAME is skipped, and WHERE says so.
function(pbf_add_cli_tool name where)
  find_package(CLI11 2 CONFIG QUIET)
  if(CLI11_FOUND)
    pbf_add_program(${name} ${ARGN} LIBS CLI11::CLI11)
  else()
    message(STATUS "${where}: ${name} skipped (needs CLI11: Debian libcli11-dev)")
  endif()
endfunction()
