# rayunits tb/gen: test-time generation -> synthesis -> Verilator -> cycle-by-cycle scoreboard.
# Run by ctest (tb/gen/CMakeLists.txt) as
#   cmake -DMODE=check|planted -DUNIT=fp_mul -DFORMAT=e7m16 -DSTAGES=3 [-DROUND=rtz]
#         [-DGEN_SYNTH=ON|OFF] [-DMUTATIONS=stages,round,loop] -DWORK=<dir> -DRAYUNITS=... -DLOADER=... -DVERILATOR=...
#         -DVERILATOR_ROOT=... -DYOSYS=... -DCXX=... -DTB_INCLUDE=... -DGLUE_IN=... -DRUGEN=...
#         -P gen_test.cmake
#
# MODE=check (every step must pass; any failure stops the script with an error):
#   1. rayunits gen <unit> --format F --stages N --round R --out WORK/mod --generic-only
#      (GEN_SYNTH=OFF: --no-synth, for big units; step 3 still synthesizes)
#   2. the datasheet says what was asked for (top name, unit, format, round, latency) and carries
#      area and depth from the flow (GEN_SYNTH=OFF: null)
#   3. yosys -s synth.ys in the generated directory (the shipped script, with check -assert)
#   4. verilator --lint-only -Wall -f files.f: no output at all
#   5. verilator --cc the generated files (--x-assign unique --x-initial unique, FST tracing);
#      the model's ports must equal the datasheet's (name, direction, width); compile model +
#      glue into WORK/libdut.so with the project's compiler
#   6. tb_gen_loader --dut=WORK/libdut.so --datasheet=WORK/mod/datasheet.json: the FP test plan
#      (special, random, reset, inject_*) must pass, every one of those tests must have run
# MODE=planted (the checks above must catch a broken generated module): for each mutation of
#   the generated wrapper, in a fresh copy of a generated directory,
#   stages  the wrapper's Stages parameter + 1 (datasheet unchanged; N+1 must not exceed the
#           unit's maximum for the format): the scoreboard must fail
#           with a missing-valid report (result not there at the datasheet's latency)
#   round   the wrapper's Round parameter changed (rtz -> rne, else -> rtz): the scoreboard must
#           fail with a y_o mismatch
#   loop    a combinational loop feeding flags_o: synth.ys must fail in check -assert
#   The copy must verilate and compile cleanly (stages, round): only the scoreboard may object.

cmake_minimum_required(VERSION 3.20)

foreach(v MODE UNIT FORMAT STAGES WORK RAYUNITS LOADER VERILATOR VERILATOR_ROOT YOSYS CXX TB_INCLUDE GLUE_IN RUGEN)
  if("${${v}}" STREQUAL "")
    message(FATAL_ERROR "gen_test.cmake: -D${v}=... is required")
  endif()
endforeach()
if(NOT ROUND)
  set(ROUND rne)
endif()
foreach(exe RAYUNITS LOADER VERILATOR YOSYS CXX)
  if(NOT EXISTS "${${exe}}")
    message(FATAL_ERROR "gen: ${exe} not found: '${${exe}}' (build tb_gen_loader and rayunits first; yosys and verilator are required)")
  endif()
endforeach()

include(${RUGEN})  # ru_gen_top_name(): the wrapper name rule
ru_gen_top_name(TOP UNIT ${UNIT} FORMAT ${FORMAT} STAGES ${STAGES} ROUND ${ROUND})

string(TIMESTAMP T0 "%s%f")
function(_gen_ms out)
  string(TIMESTAMP t "%s%f")
  math(EXPR ms "(${t} - ${T0}) / 1000")
  set(${out} ${ms} PARENT_SCOPE)
endfunction()

# _gen_run(<step> DIR <cwd> [EXPECT_FAIL] COMMAND ...): runs a command, stdout+stderr into
# WORK/<step>.log and into <step>_OUT / <step>_RC of the caller. Without EXPECT_FAIL a non-zero
# exit status stops the test (the log tail is printed).
function(_gen_run step)
  cmake_parse_arguments(A "EXPECT_FAIL" "DIR" "COMMAND" ${ARGN})
  _gen_ms(t0)
  execute_process(COMMAND ${A_COMMAND} WORKING_DIRECTORY ${A_DIR}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  _gen_ms(t1)
  math(EXPR dt "${t1} - ${t0}")
  file(WRITE ${WORK}/${step}.log "${out}")
  string(REPLACE ";" " " cmdline "${A_COMMAND}")
  message(STATUS "[gen ${TOP}] ${step}: exit ${rc}, ${dt} ms  (log ${WORK}/${step}.log)")
  if(NOT A_EXPECT_FAIL AND NOT rc EQUAL 0)
    string(LENGTH "${out}" n)
    if(n GREATER 6000)
      math(EXPR s "${n} - 6000")
      string(SUBSTRING "${out}" ${s} -1 out)
    endif()
    message(FATAL_ERROR "gen: step '${step}' failed (exit ${rc}): ${cmdline}\n${out}")
  endif()
  set(${step}_OUT "${out}" PARENT_SCOPE)
  set(${step}_RC "${rc}" PARENT_SCOPE)
endfunction()

function(_gen_fail msg)
  message(FATAL_ERROR "gen ${TOP}: ${msg}")
endfunction()

# rayunits gen into <dir> (fresh).
function(_gen_generate dir)
  file(REMOVE_RECURSE ${dir})
  _gen_run(gen DIR ${WORK} COMMAND ${RAYUNITS} gen ${UNIT} --format ${FORMAT} --stages ${STAGES}
    --round ${ROUND} --out ${dir} ${ARGN})
  if(NOT EXISTS ${dir}/${TOP}.sv OR NOT EXISTS ${dir}/files.f OR NOT EXISTS ${dir}/datasheet.json)
    _gen_fail("rayunits gen did not write ${dir}/${TOP}.sv, files.f and datasheet.json")
  endif()
endfunction()

# Verilates the generated directory <dir> and builds <so> (model + port binding glue).
function(_gen_build_dut tag dir so)
  set(obj ${WORK}/obj_${tag})
  set(prefix V${TOP})
  file(REMOVE_RECURSE ${obj})
  _gen_run(verilate_${tag} DIR ${dir} COMMAND ${VERILATOR} --cc --trace-fst -Wall
    --x-assign unique --x-initial unique --prefix ${prefix} --top-module ${TOP} -Mdir ${obj} -f files.f)

  # Ports: the model's (from Verilator's header: VL_IN8(&clk_i,0,0), VL_OUTW(&y_o,95,0,3), ...)
  # must be exactly the datasheet's.
  file(READ ${obj}/${prefix}.h hdr)
  string(REGEX MATCHALL "VL_(IN|OUT|INOUT)(8|16|64|W)?\\(&[A-Za-z0-9_]+,[0-9]+,[0-9]+" decls "${hdr}")
  set(model_ports "")
  foreach(d ${decls})
    string(REGEX MATCH "VL_(IN|OUT|INOUT)[0-9W]*\\(&([A-Za-z0-9_]+),([0-9]+),([0-9]+)" _ "${d}")
    string(TOLOWER "${CMAKE_MATCH_1}put" dirn)
    math(EXPR w "${CMAKE_MATCH_3} - ${CMAKE_MATCH_4} + 1")
    list(APPEND model_ports "${CMAKE_MATCH_2}:${dirn}:${w}")
  endforeach()
  file(READ ${dir}/datasheet.json ds)
  string(JSON np LENGTH "${ds}" ports)
  set(ds_ports "")
  set(bind "")
  math(EXPR last "${np} - 1")
  foreach(i RANGE ${last})
    string(JSON pn GET "${ds}" ports ${i} name)
    string(JSON pd GET "${ds}" ports ${i} direction)
    string(JSON pw GET "${ds}" ports ${i} width)
    list(APPEND ds_ports "${pn}:${pd}:${pw}")
    if(pw GREATER 64)
      string(APPEND bind "  pm.add(\"${pn}\", ru::tb::Port(m.${pn}.data(), ${pw}));\n")
    else()
      string(APPEND bind "  pm.add(\"${pn}\", ru::tb::Port(&m.${pn}, ${pw}));\n")
    endif()
  endforeach()
  list(SORT model_ports)
  list(SORT ds_ports)
  if(NOT model_ports STREQUAL ds_ports)
    _gen_fail("the datasheet's ports (${ds_ports}) are not the module's ports (${model_ports})")
  endif()

  file(GLOB cpps RELATIVE ${obj} ${obj}/*.cpp)
  list(SORT cpps)
  set(MODEL_INCLUDES "")
  foreach(c ${cpps})
    string(APPEND MODEL_INCLUDES "#include \"${c}\"\n")
  endforeach()
  set(PREFIX ${prefix})
  set(BIND "${bind}")
  configure_file(${GLUE_IN} ${WORK}/glue_${tag}.cpp @ONLY)
  _gen_run(compile_${tag} DIR ${WORK} COMMAND ${CXX} -std=c++17 -O1 -fPIC -shared -pthread
    -Wall -Wextra -Werror
    -DVM_TRACE=1 -DVM_TRACE_FST=1 -DVM_TRACE_VCD=0 -DVM_COVERAGE=0 -DVM_SC=0
    -isystem ${obj} -isystem ${VERILATOR_ROOT}/include -isystem ${VERILATOR_ROOT}/include/vltstd
    -I${TB_INCLUDE} ${WORK}/glue_${tag}.cpp -o ${so})
  if(NOT "${compile_${tag}_OUT}" STREQUAL "")
    _gen_fail("the model/glue compile printed diagnostics (see ${WORK}/compile_${tag}.log)")
  endif()
endfunction()

# Replaces <from> by <to> in <file>; the text must occur exactly once.
function(_gen_mutate file from to)
  file(READ ${file} s)
  string(FIND "${s}" "${from}" p)
  if(p LESS 0)
    _gen_fail("planted error: '${from}' not found in ${file} (the wrapper's form changed?)")
  endif()
  string(REPLACE "${from}" "${to}" s2 "${s}")
  string(REPLACE "${from}" "" s3 "${s}")
  string(LENGTH "${s}" l1)
  string(LENGTH "${s3}" l3)
  string(LENGTH "${from}" lf)
  math(EXPR n "(${l1} - ${l3}) / ${lf}")
  if(NOT n EQUAL 1)
    _gen_fail("planted error: '${from}' occurs ${n} times in ${file}")
  endif()
  file(WRITE ${file} "${s2}")
endfunction()

file(MAKE_DIRECTORY ${WORK})
set(LOADER_ARGS --max-errors=5 --vectors=200000)

if(MODE STREQUAL "check")
  set(mod ${WORK}/mod)
  if(GEN_SYNTH)
    _gen_generate(${mod} --generic-only)  # the generic flow fills the datasheet's area/depth
  else()
    _gen_generate(${mod} --no-synth)      # big units: only synth.ys below (one Yosys run)
  endif()

  # 2. The datasheet: the request, and the flow's numbers.
  file(READ ${mod}/datasheet.json ds)
  foreach(kv "top=${TOP}" "unit=${UNIT}" "round=${ROUND}" "latency=${STAGES}")
    string(REGEX MATCH "^([^=]+)=(.*)$" _ "${kv}")
    string(JSON got GET "${ds}" ${CMAKE_MATCH_1})
    if(NOT got STREQUAL CMAKE_MATCH_2)
      _gen_fail("datasheet.json: ${CMAKE_MATCH_1} is '${got}', expected '${CMAKE_MATCH_2}'")
    endif()
  endforeach()
  string(REGEX REPLACE "-ftz$" "" fname "${FORMAT}")
  string(JSON got GET "${ds}" format name)
  if(NOT got STREQUAL fname)
    _gen_fail("datasheet.json: format.name is '${got}', expected '${fname}'")
  endif()
  foreach(k area_nand2 depth reg_bits)
    string(JSON ty ERROR_VARIABLE e TYPE "${ds}" ${k})
    if(e)
      set(ty MISSING)
    endif()
    set(val "")
    if(ty STREQUAL "NUMBER")
      string(JSON val GET "${ds}" ${k})
    endif()
    if(GEN_SYNTH AND (NOT ty STREQUAL "NUMBER" OR NOT val GREATER 0))
      _gen_fail("datasheet.json: ${k} is ${ty} '${val}', expected a positive number from the flow")
    elseif(NOT GEN_SYNTH AND ty STREQUAL "NUMBER")
      _gen_fail("datasheet.json: ${k} is ${val} after --no-synth, expected null or absent")
    endif()
  endforeach()

  # 3. The shipped synthesis script, with check -assert, in the generated directory.
  file(STRINGS ${mod}/synth.ys ys_lines REGEX "^check -assert")
  if(NOT ys_lines)
    _gen_fail("synth.ys has no 'check -assert' line")
  endif()
  _gen_run(yosys DIR ${mod} COMMAND ${YOSYS} -q -l ${WORK}/yosys_full.log -s synth.ys)
  file(READ ${WORK}/yosys_full.log ylog)
  if(NOT ylog MATCHES "\n[0-9]+\\. Executing CHECK pass[^\n]*\n(Checking module [^\n]*\n)*Found and reported 0 problems\\.")
    _gen_fail("the Yosys log has no top-level CHECK pass with 0 problems (${WORK}/yosys_full.log)")
  endif()

  # 4. Lint: not one line of output.
  _gen_run(lint DIR ${mod} COMMAND ${VERILATOR} --lint-only -Wall --top-module ${TOP} -f files.f)
  if(NOT lint_OUT STREQUAL "")
    _gen_fail("verilator --lint-only -Wall is not clean:\n${lint_OUT}")
  endif()

  # 5. + 6. Verilate, build, run the scoreboard (every fast test of the FP plan, planted-error
  # self tests included; Long_* is the 10^6-vector run of the long label).
  _gen_build_dut(dut ${mod} ${WORK}/libdut.so)
  _gen_run(scoreboard DIR ${WORK} COMMAND ${LOADER} --dut=${WORK}/libdut.so
    --datasheet=${mod}/datasheet.json ${LOADER_ARGS} --gtest_filter=-Long_*)
  string(REGEX REPLACE "^ru_${UNIT}_" "${UNIT}_gen_" suite "${TOP}")
  foreach(t special random reset inject_bitflip inject_latency_late inject_stale)
    if(NOT scoreboard_OUT MATCHES "\\[       OK \\] ${suite}\\.${t} ")
      _gen_fail("the scoreboard run has no passing test ${suite}.${t} (${WORK}/scoreboard.log)")
    endif()
  endforeach()
  if(STAGES GREATER 0 AND NOT scoreboard_OUT MATCHES "\\[       OK \\] ${suite}\\.inject_latency_early ")
    _gen_fail("the scoreboard run has no passing test ${suite}.inject_latency_early")
  endif()
  if(scoreboard_OUT MATCHES "FAILED")
    _gen_fail("the scoreboard reported a failure (${WORK}/scoreboard.log)")
  endif()
  string(REGEX MATCH "\\[  PASSED  \\] [0-9]+ tests?" passed "${scoreboard_OUT}")
  _gen_ms(total)
  message(STATUS "[gen ${TOP}] PASS: generated, synthesized (check -assert), lint clean, ${passed} on the generated wrapper; ${total} ms")

elseif(MODE STREQUAL "planted")
  string(REPLACE "," ";" MUTATIONS "${MUTATIONS}")
  if(NOT MUTATIONS)
    message(FATAL_ERROR "gen_test.cmake: MODE=planted needs -DMUTATIONS=stages,round,loop (any of them)")
  endif()
  set(clean ${WORK}/clean)
  _gen_generate(${clean} --no-synth)
  file(STRINGS ${clean}/${TOP}.sv unit_line REGEX "^  ru_${UNIT} #\\($")
  if(NOT unit_line)
    _gen_fail("the wrapper does not instantiate ru_${UNIT} as expected ('  ru_${UNIT} #(')")
  endif()
  foreach(m ${MUTATIONS})
    set(dir ${WORK}/${m})
    file(REMOVE_RECURSE ${dir})
    file(COPY ${clean}/ DESTINATION ${dir})
    set(w ${dir}/${TOP}.sv)
    if(m STREQUAL "stages")
      math(EXPR s1 "${STAGES} + 1")
      _gen_mutate(${w} ".Stages(${STAGES})," ".Stages(${s1}),")
      set(expect "out_valid_o = 0, but the result of that input is due now")
      set(what "a missing out_valid_o")
    elseif(m STREQUAL "round")
      set(codes rne rtz rdn rup)
      list(FIND codes ${ROUND} r0)
      if(r0 EQUAL 1)
        set(r1 0)
      else()
        set(r1 1)
      endif()
      _gen_mutate(${w} ".Round(${r0})" ".Round(${r1})")
      set(expect "y_o: expected [^\n]*<-- differs")
      set(what "a y_o mismatch")
    elseif(m STREQUAL "loop")
      _gen_mutate(${w} ".flags_o     (flags_o)" ".flags_o     (flags_unit)")
      _gen_mutate(${w} "  ru_${UNIT} #(\n" "  logic [4:0] flags_unit;
  logic loop_a, loop_b;
  assign loop_a = loop_b ^ in_valid_i;  // planted: a combinational loop
  assign loop_b = loop_a & a_i[0];
  assign flags_o = flags_unit ^ {4'b0, loop_b};

  ru_${UNIT} #(\n")
      _gen_run(yosys_${m} DIR ${dir} EXPECT_FAIL COMMAND ${YOSYS} -q -l ${WORK}/yosys_${m}_full.log -s synth.ys)
      if(yosys_${m}_RC EQUAL 0 OR NOT yosys_${m}_OUT MATCHES "ERROR: Found [1-9][0-9]* problems in 'check -assert'")
        _gen_fail("planted combinational loop: synth.ys did not fail in check -assert (exit ${yosys_${m}_RC}, ${WORK}/yosys_${m}.log)")
      endif()
      message(STATUS "[gen ${TOP}] planted '${m}' caught: synth.ys failed in check -assert")
      continue()
    else()
      message(FATAL_ERROR "gen_test.cmake: unknown mutation '${m}' (stages, round, loop)")
    endif()
    _gen_build_dut(${m} ${dir} ${WORK}/libdut_${m}.so)
    _gen_run(scoreboard_${m} DIR ${WORK} EXPECT_FAIL COMMAND ${LOADER} --dut=${WORK}/libdut_${m}.so
      --datasheet=${dir}/datasheet.json ${LOADER_ARGS} --gtest_filter=*.random-Long_*)
    set(out "${scoreboard_${m}_OUT}")
    if(scoreboard_${m}_RC EQUAL 0)
      _gen_fail("planted '${m}': the scoreboard passed a broken wrapper (${WORK}/scoreboard_${m}.log)")
    endif()
    if(NOT out MATCHES "MISMATCH at cycle" OR NOT out MATCHES "${expect}")
      _gen_fail("planted '${m}': the scoreboard failed, but not with ${what} (${WORK}/scoreboard_${m}.log)")
    endif()
    string(REGEX MATCH "MISMATCH at cycle [0-9]+" first "${out}")
    message(STATUS "[gen ${TOP}] planted '${m}' caught: ${first}, ${what}")
  endforeach()
  _gen_ms(total)
  message(STATUS "[gen ${TOP}] PASS: every planted error (${MUTATIONS}) was caught; ${total} ms")
else()
  message(FATAL_ERROR "gen_test.cmake: MODE must be check or planted, not '${MODE}'")
endif()
