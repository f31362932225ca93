# rayunits: build-time module generation (`rayunits gen`) from CMake.
#
#   include(${PROJECT_SOURCE_DIR}/synth/RuGen.cmake)
#   ru_gen_unit(<var> UNIT fp_mul FORMAT e7m16 STAGES 3 [ROUND rtz] [FTZ] [PARAMS Name=V...]
#               [DIR <out dir>] [SYNTH])
#
# Adds a custom command that runs `rayunits gen ... --force --out <dir>` (with --no-synth unless
# SYNTH is given: the datasheet then has no area/depth, and the build needs no Yosys) and sets,
# in the caller's scope:
#   <var>_TOP      wrapper module name, e.g. ru_fp_mul_e7m16_s3 (same rule as the C++ wrapper_name())
#   <var>_DIR      the generated directory (default ${CMAKE_CURRENT_BINARY_DIR}/gen/<top>)
#   <var>_WRAPPER  <dir>/<top>.sv
#   <var>_SOURCES  every compile unit in the directory, in order (the unit's sources from
#                  rtl/<rtl top>.f, then the wrapper): give these to verilate(SOURCES ...)
#   <var>_FILELIST <dir>/files.f (the same list, one name per line, relative to <dir>)
# The outputs depend on the rayunits executable and on every file in rtl/, so editing the RTL
# regenerates. Output is deterministic (no timestamps), so rebuilding changes nothing.
#
# The unit's RTL module is ru_<unit> and its file list rtl/ru_<unit>.f (the convention of the
# registry in model/src/synth/units.cpp); units without a file list must be generated at
# build time only via their wrapper (<var>_WRAPPER) and `-f <var>_FILELIST`.

set(RU_GEN_CMAKE_DIR ${CMAKE_CURRENT_LIST_DIR})

# ru_gen_top_name(<out> UNIT u [FORMAT eXmY] STAGES n [ROUND r] [FTZ] [PARAMS Name=V...])
# The wrapper name rule of model/src/synth/units.cpp wrapper_name() (tests/synth checks they agree).
# PARAMS must be given only for parameters that differ from the unit's default, in the
# registry's order.
function(ru_gen_top_name out)
  cmake_parse_arguments(A "FTZ" "UNIT;FORMAT;STAGES;ROUND" "PARAMS" ${ARGN})
  set(n "ru_${A_UNIT}")
  if(A_FORMAT)
    string(REGEX REPLACE "-ftz$" "" fmt "${A_FORMAT}")
    if(NOT fmt STREQUAL A_FORMAT)
      set(A_FTZ ON)
    endif()
    string(APPEND n "_${fmt}")
  endif()
  string(APPEND n "_s${A_STAGES}")
  foreach(p ${A_PARAMS})
    if(NOT p MATCHES "^([A-Za-z][A-Za-z0-9_]*)=([0-9]+)$")
      message(FATAL_ERROR "ru_gen: PARAMS entries are Name=<non-negative int>, got '${p}'")
    endif()
    string(APPEND n "_${CMAKE_MATCH_1}${CMAKE_MATCH_2}")
  endforeach()
  if(A_FORMAT)
    if(A_ROUND AND NOT A_ROUND STREQUAL "rne")
      string(APPEND n "_${A_ROUND}")
    endif()
    if(A_FTZ)
      string(APPEND n "_ftz")
    endif()
  endif()
  set(${out} ${n} PARENT_SCOPE)
endfunction()

function(ru_gen_unit var)
  cmake_parse_arguments(A "FTZ;SYNTH" "UNIT;FORMAT;STAGES;ROUND;DIR" "PARAMS" ${ARGN})
  if(NOT A_UNIT OR "${A_STAGES}" STREQUAL "")
    message(FATAL_ERROR "ru_gen_unit(${var}): UNIT and STAGES are required")
  endif()
  set(ftz_arg "")
  if(A_FTZ)
    set(ftz_arg FTZ)
  endif()
  ru_gen_top_name(top UNIT ${A_UNIT} FORMAT "${A_FORMAT}" STAGES ${A_STAGES} ROUND "${A_ROUND}"
                  ${ftz_arg} PARAMS ${A_PARAMS})
  if(NOT A_DIR)
    set(A_DIR ${CMAKE_CURRENT_BINARY_DIR}/gen/${top})
  endif()
  set(rtl ${RU_GEN_CMAKE_DIR}/../rtl)
  get_filename_component(rtl ${rtl} ABSOLUTE)
  set(flist ${rtl}/ru_${A_UNIT}.f)
  if(NOT EXISTS ${flist})
    message(FATAL_ERROR "ru_gen_unit(${var}): ${flist} not found (unit '${A_UNIT}')")
  endif()
  file(STRINGS ${flist} lines)
  set(srcs "")
  foreach(l ${lines})
    string(REGEX REPLACE "(//|#).*$" "" l "${l}")
    string(STRIP "${l}" l)
    if(l)
      get_filename_component(b ${l} NAME)
      list(APPEND srcs ${A_DIR}/${b})
    endif()
  endforeach()
  list(APPEND srcs ${A_DIR}/${top}.sv)

  set(args ${A_UNIT} --stages ${A_STAGES} --out ${A_DIR} --force)
  if(A_FORMAT)
    list(APPEND args --format ${A_FORMAT})
  endif()
  if(A_ROUND)
    list(APPEND args --round ${A_ROUND})
  endif()
  if(A_FTZ)
    list(APPEND args --ftz)
  endif()
  foreach(p ${A_PARAMS})
    list(APPEND args --param ${p})
  endforeach()
  if(NOT A_SYNTH)
    list(APPEND args --no-synth)
  else()
    list(APPEND args --generic-only)
  endif()
  file(GLOB rtl_files CONFIGURE_DEPENDS ${rtl}/*)
  add_custom_command(
    OUTPUT ${srcs} ${A_DIR}/files.f ${A_DIR}/datasheet.json
    COMMAND rayunits gen ${args}
    DEPENDS rayunits ${rtl_files}
    COMMENT "rayunits gen ${top}"
    VERBATIM)
  set(${var}_TOP ${top} PARENT_SCOPE)
  set(${var}_DIR ${A_DIR} PARENT_SCOPE)
  set(${var}_WRAPPER ${A_DIR}/${top}.sv PARENT_SCOPE)
  set(${var}_SOURCES ${srcs} PARENT_SCOPE)
  set(${var}_FILELIST ${A_DIR}/files.f PARENT_SCOPE)
endfunction()
