# rayunits tb: CMake helpers for Verilated cycle-by-cycle scoreboard tests (see tb/README.md).
#
#   ru_tb_unit(<unit>)
#       Declares a unit from the unit registry (model/data/registry.json, written by
#       `rayunits registry --json` from model/src/synth/units.cpp; ctest Registry.JsonIsCurrent
#       fails when it is stale): its RTL module, the file list rtl/<top>.f, its ports (widths are
#       expressions in W (= 1+E+M), E (= ExpW), M (= FracW) and the unit's parameters, e.g.
#       "a_i:3*W"), its parameter defaults (used where a configuration does not override them) and
#       its maximum useful Stages (the smax token below). Nothing about a unit is written here.
#
#   ru_tb_add_tests(<target> UNIT <unit> CONFIGS <cfg>... [LONG] [NO_TRACE] [NO_LINT])
#       One executable <target>; one Verilator model per configuration (unique PREFIX
#       V<unit>_<config>), all linked with ONE copy of the Verilator runtime, the harness and
#       the unit's adapter. GoogleTest cases are registered at run time by the unit's test plan
#       (tb/units/*.cpp) and discovered by ctest: <unit>_<config>.<test>, and
#       Long_<unit>_<config>.<test> with the ctest label `long`. LONG prefixes every test
#       of the target with Long_ (label long). A lint test <unit>_<config>.lint
#       (verilator --lint-only -Wall) is added per configuration unless NO_LINT.
#
# Configuration syntax: "[<format>:]s<Stages>[:<round>][:Name=<int>...][:<tag>...]", tokens
# separated by ':'
#   s<Stages> a number, or smax / smax+<n> / smax-<n>: the registry's maximum useful Stages of
#             the unit for this format and parameters (the configuration's name has the number)
#   <format>  eXmY or eXmY-ftz: ExpW=X FracW=Y Subnormals=1|0 (and Round, default rne);
#             omit it for units without a floating-point format (no W/E/M in port widths)
#   <round>   rne | rtz | rdn | rup: Round=0..3
#   Name=int  any other RTL parameter override (part of the configuration name)
#   tags      exhaustive (all operand combinations), selftest (planted-error tests),
#             n=<count> (random vectors); lower-case, not part of the name
# e.g. "e8m23:s3", "e5m10-ftz:s2:rtz", "e4m3:s1:exhaustive", "e11m52:s9:n=1000000",
# "s4:FracBits=8". Names: e8m23_s3, e5m10_ftz_s2_rtz, s4_FracBits8.

set(RU_TB_DIR ${CMAKE_CURRENT_LIST_DIR}/..)
# Where the units' RTL is read from (`rayunits rtl --rtl DIR` points its build cache elsewhere).
set(RU_TB_RTL_DIR ${PROJECT_SOURCE_DIR}/rtl CACHE PATH "RTL source directory of the Verilated units")

# Verilator's runtime, shared by every Verilated executable of the project.
if(NOT TARGET ru_tb_vlrt)
  find_package(ZLIB REQUIRED)  # FST writer
  add_library(ru_tb_vlrt STATIC ${VERILATOR_ROOT}/include/verilated.cpp
    ${VERILATOR_ROOT}/include/verilated_fst_c.cpp ${VERILATOR_ROOT}/include/verilated_threads.cpp)
  target_include_directories(ru_tb_vlrt SYSTEM PUBLIC ${VERILATOR_ROOT}/include ${VERILATOR_ROOT}/include/vltstd)
  target_compile_definitions(ru_tb_vlrt PRIVATE VM_TRACE=1 VM_TRACE_FST=1 VM_TRACE_VCD=0 VM_COVERAGE=0 VM_SC=0)
  target_compile_options(ru_tb_vlrt PRIVATE -w ${RU_TB_OPT_GLOBAL})
  target_link_libraries(ru_tb_vlrt PUBLIC ZLIB::ZLIB Threads::Threads)
endif()

set(RU_REGISTRY_JSON ${CMAKE_CURRENT_LIST_DIR}/../../model/data/registry.json)
set(RU_TB_EXTRA_REGISTRY "" CACHE FILEPATH "Registry JSON of run-time datapath units (rayunits rtl's build cache)")
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${RU_REGISTRY_JSON})

function(ru_tb_unit unit)
  if(ARGN)
    message(FATAL_ERROR "ru_tb_unit(${unit} ${ARGN}): a unit is described by its registry entry only "
      "(model/src/synth/units.cpp -> rayunits registry --json model/data/registry.json)")
  endif()
  # The registry, then (rayunits rtl of a datapath design given at run time, $RU_DP_DESIGNS) the
  # registry JSON of the run-time units the cache wrote for this build.
  set(idx -1)
  foreach(regfile ${RU_REGISTRY_JSON} ${RU_TB_EXTRA_REGISTRY})
    if(idx LESS 0)
      file(READ ${regfile} reg)
      string(JSON n LENGTH "${reg}" units)
      math(EXPR last "${n} - 1")
      foreach(i RANGE ${last})
        string(JSON nm GET "${reg}" units ${i} name)
        if(nm STREQUAL unit)
          set(idx ${i})
        endif()
      endforeach()
    endif()
  endforeach()
  if(idx LESS 0)
    message(FATAL_ERROR "ru_tb_unit(${unit}): no such unit in ${RU_REGISTRY_JSON} ${RU_TB_EXTRA_REGISTRY}")
  endif()
  string(JSON top GET "${reg}" units ${idx} top)
  string(JSON fl GET "${reg}" units ${idx} filelist)
  string(JSON maxs GET "${reg}" units ${idx} max_stages)
  set(ports "")
  string(JSON np LENGTH "${reg}" units ${idx} ports)
  math(EXPR plast "${np} - 1")
  foreach(i RANGE ${plast})
    string(JSON pn GET "${reg}" units ${idx} ports ${i} name)
    string(JSON pw GET "${reg}" units ${idx} ports ${i} width)
    list(APPEND ports "${pn}:${pw}")
  endforeach()
  set(defaults "")
  string(JSON nx LENGTH "${reg}" units ${idx} params)
  if(nx GREATER 0)
    math(EXPR xlast "${nx} - 1")
    foreach(i RANGE ${xlast})
      string(JSON xn GET "${reg}" units ${idx} params ${i} name)
      string(JSON xd GET "${reg}" units ${idx} params ${i} default)
      list(APPEND defaults "${xn}=${xd}")
    endforeach()
  endif()
  set_property(GLOBAL PROPERTY RU_TB_UNIT_${unit}_MODULE ${top})
  set_property(GLOBAL PROPERTY RU_TB_UNIT_${unit}_FILELIST "${RU_TB_RTL_DIR}/${fl}")
  set_property(GLOBAL PROPERTY RU_TB_UNIT_${unit}_SOURCES "")
  set_property(GLOBAL PROPERTY RU_TB_UNIT_${unit}_PORTS "${ports}")
  set_property(GLOBAL PROPERTY RU_TB_UNIT_${unit}_DEFAULTS "${defaults}")
  set_property(GLOBAL PROPERTY RU_TB_UNIT_${unit}_MAXSTAGES "${maxs}")
  string(JSON large GET "${reg}" units ${idx} large_model)
  set_property(GLOBAL PROPERTY RU_TB_UNIT_${unit}_LARGE "${large}")
endfunction()

# ru_fp_pkg::csa_levels(n): carry-save levels that reduce n partial products to two.
function(_ru_tb_csa_levels n out)
  set(l 0)
  while(n GREATER 2)
    math(EXPR n "2 * (${n} / 3) + ${n} % 3")
    math(EXPR l "${l} + 1")
  endwhile()
  set(${out} ${l} PARENT_SCOPE)
endfunction()

# Evaluates a registry expression (port width, max Stages) for a list of Name=Value parameters:
# the names E, M, W, L (from ExpW/FracW), every parameter, and max(x, y).
function(_ru_tb_eval expr params what out)
  set(vars "")
  foreach(p ${params})
    string(REPLACE "=" ";" kv ${p})
    list(GET kv 0 k)
    list(GET kv 1 v)
    set(P_${k} ${v})
    list(APPEND vars ${k})
  endforeach()
  if(DEFINED P_ExpW AND DEFINED P_FracW)  # floating-point configurations
    math(EXPR P_W "1 + ${P_ExpW} + ${P_FracW}")
    set(P_E ${P_ExpW})
    set(P_M ${P_FracW})
    math(EXPR n1 "${P_FracW} + 1")
    _ru_tb_csa_levels(${n1} P_L)
    list(APPEND vars W E M L)
  endif()
  string(REGEX MATCHALL "[A-Za-z_][A-Za-z0-9_]*|[^A-Za-z_]+" toks "${expr}")
  set(e "")
  foreach(tk ${toks})
    if(tk STREQUAL "max")  # max(x, y): evaluated below
    elseif(tk MATCHES "^[A-Za-z_]")
      if(NOT tk IN_LIST vars)
        message(FATAL_ERROR "ru_tb: ${what}: unknown name '${tk}' in '${expr}' (known: ${vars})")
      endif()
      set(tk "${P_${tk}}")
    endif()
    string(APPEND e "${tk}")
  endforeach()
  # max(x, y), innermost first (math(EXPR) has no max)
  while(e MATCHES "max\\(([^(),]*),([^(),]*)\\)")
    set(call "${CMAKE_MATCH_0}")
    math(EXPR x "${CMAKE_MATCH_1}")
    math(EXPR y "${CMAKE_MATCH_2}")
    if(x LESS y)
      set(x ${y})
    endif()
    string(REPLACE "${call}" "${x}" e "${e}")
  endwhile()
  math(EXPR v "${e}")
  set(${out} ${v} PARENT_SCOPE)
endfunction()

# Replaces an smax / smax+n / smax-n token of a configuration by s<number> (the unit's maximum
# useful Stages from the registry for the configuration's format and parameters).
function(_ru_tb_resolve_smax unit cfg out)
  if(NOT cfg MATCHES "(^|:)smax([+-][0-9]+)?(:|$)")
    set(${out} "${cfg}" PARENT_SCOPE)
    return()
  endif()
  set(delta "${CMAKE_MATCH_2}")  # (not `off`: if(off) would read the constant OFF)
  string(REGEX REPLACE "(^|:)smax([+-][0-9]+)?(:|$)" "\\1s0\\3" probe "${cfg}")
  _ru_tb_parse_config("${probe}" C)
  get_property(defaults GLOBAL PROPERTY RU_TB_UNIT_${unit}_DEFAULTS)
  set(params ${C_PARAMS})
  foreach(d ${defaults})
    string(REGEX REPLACE "=.*" "" dk "${d}")
    if(NOT params MATCHES "(^|;)${dk}=")
      list(APPEND params ${d})
    endif()
  endforeach()
  get_property(maxs GLOBAL PROPERTY RU_TB_UNIT_${unit}_MAXSTAGES)
  _ru_tb_eval("${maxs}" "${params}" "${unit} max Stages" m)
  if(NOT delta STREQUAL "")
    math(EXPR m "${m} ${delta}")
  endif()
  string(REGEX REPLACE "(^|:)smax([+-][0-9]+)?(:|$)" "\\1s${m}\\3" r "${cfg}")
  set(${out} "${r}" PARENT_SCOPE)
endfunction()

# Parses one configuration string into variables in the caller's scope:
# <out>_NAME, <out>_PARAMS (list of Name=Value), <out>_TAGS (list).
function(_ru_tb_parse_config cfg out)
  string(REPLACE ":" ";" toks "${cfg}")
  set(name "")
  set(params "")
  set(tags "")
  set(round "")
  set(have_stages 0)
  foreach(t ${toks})
    if(t MATCHES "^e([0-9]+)m([0-9]+)(-ftz)?$" AND name STREQUAL "")
      set(sub 1)
      set(name "e${CMAKE_MATCH_1}m${CMAKE_MATCH_2}")
      if(CMAKE_MATCH_3)
        set(sub 0)
        string(APPEND name "_ftz")
      endif()
      list(APPEND params ExpW=${CMAKE_MATCH_1} FracW=${CMAKE_MATCH_2} Subnormals=${sub})
      set(round 0)
    elseif(t MATCHES "^s([0-9]+)$")
      set(have_stages 1)
      list(APPEND params Stages=${CMAKE_MATCH_1})
      string(APPEND name "_s${CMAKE_MATCH_1}")
    elseif(t MATCHES "^(rne|rtz|rdn|rup)$")
      list(FIND _RU_TB_ROUNDS ${t} round)
      if(NOT t STREQUAL "rne")
        string(APPEND name "_${t}")
      endif()
    elseif(t MATCHES "^([A-Z][A-Za-z0-9_]*)=(-?[0-9]+)$")
      list(APPEND params "${t}")
      string(APPEND name "_${CMAKE_MATCH_1}${CMAKE_MATCH_2}")
    elseif(t MATCHES "^[a-z][a-z0-9_]*(=[A-Za-z0-9_.+-]+)?$")
      list(APPEND tags "${t}")
    else()
      message(FATAL_ERROR "ru_tb: bad token '${t}' in configuration '${cfg}' "
        "(expected [eXmY[-ftz]:]sN[:rne|rtz|rdn|rup][:Name=int][:tag][:n=count])")
    endif()
  endforeach()
  if(NOT have_stages)
    message(FATAL_ERROR "ru_tb: configuration '${cfg}' has no s<Stages> token")
  endif()
  if(NOT round STREQUAL "")
    list(APPEND params Round=${round})
  endif()
  string(REGEX REPLACE "^_" "" name "${name}")
  set(${out}_NAME ${name} PARENT_SCOPE)
  set(${out}_PARAMS ${params} PARENT_SCOPE)
  set(${out}_TAGS "${tags}" PARENT_SCOPE)
endfunction()
set(_RU_TB_ROUNDS rne rtz rdn rup)

# Reads a Verilator .f file list (one path per line, '//' or '#' comments) into absolute paths.
function(_ru_tb_read_filelist f out)
  get_filename_component(dir ${f} DIRECTORY)
  file(STRINGS ${f} lines)
  set(files "")
  foreach(l ${lines})
    string(REGEX REPLACE "(//|#).*$" "" l "${l}")
    string(STRIP "${l}" l)
    if(l STREQUAL "")
      continue()
    endif()
    if(l MATCHES "^[-+]")
      message(FATAL_ERROR "ru_tb: ${f}: only plain file names are supported in the file list ('${l}')")
    endif()
    if(NOT IS_ABSOLUTE ${l})
      set(l ${dir}/${l})
    endif()
    list(APPEND files ${l})
  endforeach()
  set(${out} ${files} PARENT_SCOPE)
endfunction()

# -I<dir> for every directory holding one of the sources (for `include files next to them).
function(_ru_tb_incdirs srcs out)
  set(dirs "")
  foreach(s ${srcs})
    get_filename_component(d ${s} DIRECTORY)
    list(APPEND dirs -I${d})
  endforeach()
  list(REMOVE_DUPLICATES dirs)
  set(${out} ${dirs} PARENT_SCOPE)
endfunction()

# Checks that <unit>'s RTL exists and elaborates (first configuration); sets <out> to its
# source files, or to "" (with a STATUS/WARNING message) when the unit cannot be built yet.
function(_ru_tb_unit_sources target unit configs out)
  set(${out} "" PARENT_SCOPE)
  get_property(known GLOBAL PROPERTY RU_TB_SRCS_${target}_${unit} SET)
  if(known)  # already checked for this target
    get_property(srcs GLOBAL PROPERTY RU_TB_SRCS_${target}_${unit})
    set(${out} "${srcs}" PARENT_SCOPE)
    return()
  endif()
  set_property(GLOBAL PROPERTY RU_TB_SRCS_${target}_${unit} "")
  get_property(module GLOBAL PROPERTY RU_TB_UNIT_${unit}_MODULE)
  get_property(filelist GLOBAL PROPERTY RU_TB_UNIT_${unit}_FILELIST)
  get_property(srcs GLOBAL PROPERTY RU_TB_UNIT_${unit}_SOURCES)
  get_property(ports GLOBAL PROPERTY RU_TB_UNIT_${unit}_PORTS)
  if(NOT module)
    message(FATAL_ERROR "ru_tb_add_tests(${target}): unknown unit '${unit}' (declare it with ru_tb_unit)")
  endif()
  if(filelist)
    if(NOT EXISTS ${filelist})
      message(STATUS "ru_tb: ${target} skipped: ${filelist} does not exist (yet)")
      return()
    endif()
    _ru_tb_read_filelist(${filelist} flsrcs)
    list(APPEND srcs ${flsrcs})
  endif()
  foreach(s ${srcs})
    if(NOT EXISTS ${s})
      message(STATUS "ru_tb: ${target} skipped: ${s} does not exist (yet)")
      return()
    endif()
  endforeach()

  # Configure-time sanity check: Verilator must elaborate the first configuration, otherwise
  # verilate() would stop the whole project's configure. A broken unit gets a failing test.
  list(GET configs 0 first_cfg)
  _ru_tb_resolve_smax(${unit} "${first_cfg}" first_cfg)
  _ru_tb_parse_config("${first_cfg}" C)
  set(gargs "")
  foreach(p ${C_PARAMS})
    list(APPEND gargs -G${p})
  endforeach()
  _ru_tb_incdirs("${srcs}" incs)
  execute_process(
    COMMAND ${VERILATOR_BIN} --lint-only -Wno-fatal -Wno-lint -Wno-style --top-module ${module} ${incs} ${gargs} ${srcs}
    RESULT_VARIABLE rc OUTPUT_VARIABLE vout ERROR_VARIABLE vout)
  if(rc)
    message(WARNING "ru_tb: ${target}: Verilator cannot elaborate ${module} (${C_NAME}); its tests are replaced by a failing placeholder:\n${vout}")
    add_test(NAME ${unit}_${C_NAME}.rtl_does_not_elaborate
      COMMAND ${VERILATOR_BIN} --lint-only -Wno-fatal --top-module ${module} ${gargs} ${srcs})
    return()
  endif()

  set_property(GLOBAL PROPERTY RU_TB_SRCS_${target}_${unit} "${srcs}")
  set(${out} ${srcs} PARENT_SCOPE)
endfunction()

# ru_tb_add_models(<target> UNIT <unit> CONFIGS <cfg>... [NO_TRACE] [NO_LINT] [LONG])
#   Adds one Verilated model per configuration (and its registration glue) to an existing
#   executable <target> (used by ru_tb_add_tests and by the benchmark). Sets <target>_MODELS
#   in the caller's scope to the number of models added (0 when the unit's RTL is missing).
function(ru_tb_add_models target)
  cmake_parse_arguments(A "LONG;NO_TRACE;NO_LINT" "UNIT" "CONFIGS" ${ARGN})
  set(${target}_MODELS 0 PARENT_SCOPE)
  set(unit ${A_UNIT})
  _ru_tb_unit_sources(${target} ${unit} "${A_CONFIGS}" srcs)
  if(NOT srcs)
    return()
  endif()
  get_property(module GLOBAL PROPERTY RU_TB_UNIT_${unit}_MODULE)
  get_property(ports GLOBAL PROPERTY RU_TB_UNIT_${unit}_PORTS)
  _ru_tb_incdirs("${srcs}" incs)
  set(common_args -Wall -Wno-fatal --x-assign unique --x-initial unique ${incs})
  if(RU_TB_VERILATOR_ARGS)
    list(APPEND common_args ${RU_TB_VERILATOR_ARGS})
  endif()

  set(gendir ${CMAKE_CURRENT_BINARY_DIR}/gen/${target})
  set(all_names "")
  foreach(cfg ${A_CONFIGS})
    _ru_tb_resolve_smax(${unit} "${cfg}" cfg)
    _ru_tb_parse_config("${cfg}" C)
    if(C_NAME IN_LIST all_names)
      message(FATAL_ERROR "ru_tb_add_tests(${target}): configuration ${C_NAME} given twice")
    endif()
    list(APPEND all_names ${C_NAME})
    set(tags ${C_TAGS})
    if(A_LONG)
      list(APPEND tags long)
    endif()
    set(prefix V${unit}_${C_NAME})
    # The unit's defaults for parameters this configuration does not set.
    get_property(defaults GLOBAL PROPERTY RU_TB_UNIT_${unit}_DEFAULTS)
    foreach(d ${defaults})
      string(REGEX REPLACE "=.*" "" dk "${d}")
      if(NOT C_PARAMS MATCHES "(^|;)${dk}=")
        list(APPEND C_PARAMS ${d})
      endif()
    endforeach()
    set(bind "")
    foreach(pdesc ${ports})
      string(REPLACE ":" ";" pd ${pdesc})
      list(GET pd 0 pname)
      list(GET pd 1 pexpr)
      _ru_tb_eval("${pexpr}" "${C_PARAMS}" "${unit}: port ${pname}" pw)
      if(pw GREATER 64)
        set(ptr "m.${pname}.data()")
      else()
        set(ptr "&m.${pname}")
      endif()
      string(APPEND bind "  pm.add(\"${pname}\", ru::tb::Port(${ptr}, ${pw}));\n")
    endforeach()
    set(cparams "")
    set(gargs "")
    foreach(p ${C_PARAMS})
      string(REPLACE "=" ";" kv ${p})
      list(GET kv 0 k)
      list(GET kv 1 v)
      string(APPEND cparams "{\"${k}\", ${v}}, ")
      list(APPEND gargs -G${p})
    endforeach()
    set(ctags "")
    foreach(t ${tags})
      string(APPEND ctags "\"${t}\", ")
    endforeach()
    file(CONFIGURE OUTPUT ${gendir}/${prefix}_glue.cpp @ONLY CONTENT
"// Generated by tb/cmake/RuTb.cmake for ${unit} ${C_NAME}: do not edit.
#include \"${prefix}.h\"
#include \"rayunits/tb/verilated_dut.hpp\"

namespace {
void bind_ports(${prefix}& m, ru::tb::PortMap& pm) {
${bind}}
ru::tb::ConfigRegistrar reg{ru::tb::ConfigDesc{
    \"${unit}\", \"${C_NAME}\", \"${prefix}\", {${cparams}}, {${ctags}},
    [](const ru::tb::DutOptions& o) -> std::unique_ptr<ru::tb::Dut> {
      return std::make_unique<ru::tb::VerilatedDut<${prefix}>>(o, &bind_ports);
    }}};
}  // namespace
")
    target_sources(${target} PRIVATE ${gendir}/${prefix}_glue.cpp)
    set(trace_opt TRACE_FST)
    if(A_NO_TRACE)
      set(trace_opt "")
    endif()
    verilate(${target} PREFIX ${prefix} TOP_MODULE ${module} ${trace_opt}
      SOURCES ${srcs}
      VERILATOR_ARGS ${common_args} ${gargs})
    # Build cost: Verilator writes ~9 small .cpp files per model and every one of them parses
    # the heavy Verilator headers. Compile them as two unity translation units per model
    # instead (fast path with RU_TB_OPT_FAST, constructors/tracing with RU_TB_OPT_SLOW): 3-4x
    # less compile time for the small FP units. The generated files stay in the target as
    # HEADER_FILE_ONLY so that Verilator's custom command still (re)generates them.
    set(vdir ${CMAKE_CURRENT_BINARY_DIR}/CMakeFiles/${target}.dir/${prefix}.dir)
    include(${vdir}/${prefix}_copy.cmake)
    set(part_fast ${${prefix}_CLASSES_FAST} ${${prefix}_SUPPORT_FAST})
    set(part_slow ${${prefix}_CLASSES_SLOW} ${${prefix}_SUPPORT_SLOW})
    foreach(kind fast slow)
      set(ufile ${gendir}/${prefix}__${kind}_unity.cpp)
      set(content "// Generated by tb/cmake/RuTb.cmake: unity build of ${prefix} (${kind} part).\n")
      foreach(f ${part_${kind}})
        string(APPEND content "#include \"${f}\"\n")
      endforeach()
      file(CONFIGURE OUTPUT ${ufile} CONTENT "${content}" @ONLY)
      set_source_files_properties(${part_${kind}} PROPERTIES HEADER_FILE_ONLY ON)
      if(kind STREQUAL "fast")
        set(uopt ${RU_TB_OPT_FAST})
      else()
        set(uopt ${RU_TB_OPT_SLOW})
      endif()
      set_source_files_properties(${ufile} PROPERTIES OBJECT_DEPENDS "${part_${kind}}"
        COMPILE_OPTIONS "-w;${uopt}")
      target_sources(${target} PRIVATE ${ufile})
    endforeach()
    if(NOT A_NO_LINT)
      add_test(NAME ${unit}_${C_NAME}.lint
        COMMAND ${VERILATOR_BIN} --lint-only -Wall --top-module ${module} ${incs} ${gargs} ${srcs})
      if(A_LONG)
        set_tests_properties(${unit}_${C_NAME}.lint PROPERTIES LABELS long)
      endif()
    endif()
  endforeach()
  # Verilator's runtime (verilated.cpp, verilated_fst_c.cpp, verilated_threads.cpp) is
  # compiled once for all executables (ru_tb_vlrt) instead of once per verilate() target.
  get_target_property(tsrcs ${target} SOURCES)
  list(FILTER tsrcs EXCLUDE REGEX "^${VERILATOR_ROOT}/include/.*\\.cpp$")
  set_property(TARGET ${target} PROPERTY SOURCES ${tsrcs})
  target_link_libraries(${target} PRIVATE ru_tb_vlrt)
  # Verilator's headers and the generated model headers are SYSTEM includes, so the glue code
  # stays -Wall -Wextra clean.
  get_target_property(tincs ${target} INCLUDE_DIRECTORIES)
  target_include_directories(${target} SYSTEM PRIVATE ${tincs})
  list(LENGTH all_names n)
  set(${target}_MODELS ${n} PARENT_SCOPE)
endfunction()

# ru_tb_registry_tests(): tb_<unit> for every unit of the registry, with the configurations of its
# "tests" list, and tb_<unit>_long (label long) from "long_tests" when RU_TB_LONG is on. Units
# with "large_model" are built with RU_TB_LARGE_OPT and without FST tracing unless
# RU_TB_LARGE_TRACE. A unit added to the registry gets its executable here with nothing else.
function(ru_tb_registry_tests)
  file(READ ${RU_REGISTRY_JSON} reg)
  string(JSON n LENGTH "${reg}" units)
  math(EXPR last "${n} - 1")
  set(RU_TB_OPT_FAST_SAVED "${RU_TB_OPT_FAST}")
  set(RU_TB_OPT_SLOW_SAVED "${RU_TB_OPT_SLOW}")
  foreach(i RANGE ${last})
    string(JSON unit GET "${reg}" units ${i} name)
    ru_tb_unit(${unit})
    get_property(large GLOBAL PROPERTY RU_TB_UNIT_${unit}_LARGE)
    set(opts "")
    if(large)
      set(RU_TB_OPT_FAST ${RU_TB_LARGE_OPT})  # function scope: shadows the cache variables
      set(RU_TB_OPT_SLOW ${RU_TB_LARGE_OPT})
      if(NOT RU_TB_LARGE_TRACE)
        set(opts NO_TRACE)
      endif()
    else()
      set(RU_TB_OPT_FAST "${RU_TB_OPT_FAST_SAVED}")
      set(RU_TB_OPT_SLOW "${RU_TB_OPT_SLOW_SAVED}")
    endif()
    foreach(kind tests long_tests)
      set(cfgs "")
      string(JSON nt LENGTH "${reg}" units ${i} ${kind})
      if(nt GREATER 0)
        math(EXPR tlast "${nt} - 1")
        foreach(k RANGE ${tlast})
          string(JSON c GET "${reg}" units ${i} ${kind} ${k})
          list(APPEND cfgs "${c}")
        endforeach()
      endif()
      if(NOT cfgs)
        continue()
      endif()
      if(kind STREQUAL "tests")
        ru_tb_add_tests(tb_${unit} UNIT ${unit} ${opts} CONFIGS ${cfgs})
      elseif(RU_TB_LONG)
        ru_tb_add_tests(tb_${unit}_long UNIT ${unit} LONG ${opts} CONFIGS ${cfgs})
      endif()
    endforeach()
  endforeach()
endfunction()

function(ru_tb_add_tests target)
  cmake_parse_arguments(A "LONG;NO_TRACE;NO_LINT" "UNIT" "CONFIGS" ${ARGN})
  _ru_tb_unit_sources(${target} ${A_UNIT} "${A_CONFIGS}" srcs)
  if(NOT srcs)
    return()  # the unit's RTL is missing or broken (see the message): no executable
  endif()
  add_executable(${target} $<TARGET_OBJECTS:ru_tb_main>)
  target_link_libraries(${target} PRIVATE ru_tb_units ru_tb_core rayunits_model GTest::gtest Threads::Threads)
  target_compile_options(${target} PRIVATE ${RU_WARN})
  ru_tb_add_models(${target} ${ARGN})
  if(A_LONG)
    gtest_discover_tests(${target} PROPERTIES LABELS long DISCOVERY_TIMEOUT 120
      WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  else()
    gtest_discover_tests(${target} TEST_FILTER "-Long*" DISCOVERY_TIMEOUT 120
      WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
    gtest_discover_tests(${target} TEST_FILTER "Long*" PROPERTIES LABELS long DISCOVERY_TIMEOUT 120
      WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  endif()
endfunction()

# ru_tb_add_job(<target> UNIT <unit> CONFIG <cfg>)
#   One executable of `rayunits rtl`'s build cache: the unit's test plan for one configuration,
#   without tracing or a lint test, not registered with ctest (the rtl command runs it).
function(ru_tb_add_job target)
  cmake_parse_arguments(A "" "UNIT;CONFIG" "" ${ARGN})
  ru_tb_unit(${A_UNIT})
  get_property(large GLOBAL PROPERTY RU_TB_UNIT_${A_UNIT}_LARGE)
  if(large)  # as ru_tb_registry_tests builds the unit's own tests
    set(RU_TB_OPT_FAST ${RU_TB_LARGE_OPT})
    set(RU_TB_OPT_SLOW ${RU_TB_LARGE_OPT})
  endif()
  _ru_tb_unit_sources(${target} ${A_UNIT} "${A_CONFIG}" srcs)
  if(NOT srcs)
    message(FATAL_ERROR "ru_tb_add_job(${target}): the RTL of ${A_UNIT} is missing or does not elaborate (see above)")
  endif()
  add_executable(${target} $<TARGET_OBJECTS:ru_tb_main>)
  target_link_libraries(${target} PRIVATE ru_tb_units ru_tb_core rayunits_model GTest::gtest Threads::Threads)
  target_compile_options(${target} PRIVATE ${RU_WARN})
  ru_tb_add_models(${target} UNIT ${A_UNIT} CONFIGS ${A_CONFIG} NO_TRACE NO_LINT)
endfunction()

# ru_tb_add_cosim_job(<target> <unit>:<config>...)
#   The TRaX co-simulation companion (tb/trax/cosim_main.cpp) with exactly these unit
#   configurations, for `rayunits trax --cosim-build` (model/src/rtl/cache.cpp); models at -O1
#   and without tracing, as tb/trax builds tb_trax_cosim.
function(ru_tb_add_cosim_job target)
  set(RU_TB_OPT_FAST -O1)  # function scope: shadows the cache variables
  set(RU_TB_OPT_SLOW -O1)
  add_executable(${target} ${RU_TB_DIR}/trax/cosim_main.cpp)
  target_link_libraries(${target} PRIVATE ru_tb_core rayunits_model Threads::Threads)
  target_compile_options(${target} PRIVATE ${RU_WARN})
  foreach(uc ${ARGN})
    if(NOT uc MATCHES "^([a-z0-9_]+):(.+)$")
      message(FATAL_ERROR "ru_tb_add_cosim_job(${target}): '${uc}' is not <unit>:<config>")
    endif()
    set(u ${CMAKE_MATCH_1})
    set(c ${CMAKE_MATCH_2})
    ru_tb_unit(${u})
    ru_tb_add_models(${target} UNIT ${u} CONFIGS ${c} NO_TRACE NO_LINT)
  endforeach()
endfunction()
