# rayunits tb/gls: gate-level simulation of the osu018-mapped netlist under the cycle-by-cycle
# scoreboard (issue 13 section 2). Run by ctest (tb/gls/CMakeLists.txt) as
#   cmake -DMODE=cells|netlist|planted -DWORK=<dir> -DLIB=<liberty> -DCELLS_V=<vendor cell .v>
#         -DYOSYS=... -DIVERILOG=... -DVVP=...                                  (every mode)
#         -DMODELS=<osu018_cells.v>                                             (netlist, planted)
#         -DUNIT=fp_add -DFORMAT=e5m10 -DSTAGES=2 [-DROUND=rne] [-DTAGS=exhaustive]
#         -DRAYUNITS=... -DLOADER=... -DVERILATOR=... -DVERILATOR_ROOT=... -DCXX=...
#         -DTB_INCLUDE=... -DGLUE_IN=... -DRUGEN=... [-DVECTORS=N]                (netlist, planted)
#         -P gls_test.cmake
#
# MODE=cells: cell models for Verilator, written by Yosys from the liberty, checked cell by cell
#   1. yosys: read_liberty LIB (without -lib: each cell's `function` / `ff` / `latch` group becomes
#      logic), the three-state cells deleted (TBUFX1/TBUFX2: their `three_state` attribute is not
#      modelled, and abc never maps to them), write_verilog -noattr -> WORK/osu018_cells.v
#   2. Icarus: one testbench (generated here from the liberty's cell list, yosys write_json)
#      instantiates every cell twice, the model and the vendor's osu018_stdcells.v cell (renamed
#      ref_<cell>, with its UDPs), and compares every output with !== after each input change:
#      combinational cells every input combination, sequential cells (a CLK pin) a random walk of
#      SEQ_STEPS single-input toggles (clock edges with stable data, async set/reset in every
#      order), compared once the vendor model's output has left its power-up x. One exception,
#      excluded in every netlist instead (MODE=netlist step 3): in the DFFSR walk, releasing R
#      while S is low is skipped (the UDP then sets Q at once; the edge-triggered model, whose
#      sensitivity list has only the falling edges of R and S, keeps Q = 0 until the next clock
#      edge). Both low (R dominates) and releasing S while R is low are checked.
#   Every liberty cell must be checked or listed as excluded; any mismatch fails (listed by cell).
# MODE=netlist: the mapped netlist on the scoreboard
#   1. rayunits gen <unit> --no-synth --out WORK/mod: the wrapper, its RTL, files.f, datasheet
#   2. rayunits synth --flow osu018 --clock 2ns --netlist: the synthesis flow maps it -> netlist.v
#   3. the netlist: only liberty cells, no three-state cell, every DFFSR with R or S tied to 1
#   4. verilator --cc netlist.v osu018_cells.v (--x-assign unique --x-initial unique,
#      -fno-const-bit-op-tree: see VERILATOR_GLS_ARGS), ports equal the datasheet's; model + glue
#      (tb/gen/gen_glue.cpp.in) -> WORK/libdut.so
#   5. tb_gen_loader --config-name=gls_<format>_s<N> (suite <unit>_gls_<...>): the FP test plan
#      (special, random, reset, exhaustive with TAGS=exhaustive, the inject_* self tests)
# MODE=planted: the same flow must catch
#   cellfn  one minterm of one cell model wrong (OAI21X1, A=B=C=1): the Icarus cell check must
#           report exactly that cell and combination, and the scoreboard on the netlist simulated
#           with that model must fail with a data mismatch
#   gate    the netlist gate driving y_o[0] with its output inverted (an INVX1 inserted): the
#           scoreboard must fail with a y_o mismatch

cmake_minimum_required(VERSION 3.20)

foreach(v MODE WORK LIB CELLS_V YOSYS IVERILOG VVP)
  if("${${v}}" STREQUAL "")
    message(FATAL_ERROR "gls_test.cmake: -D${v}=... is required")
  endif()
endforeach()
foreach(f LIB CELLS_V YOSYS IVERILOG VVP)
  if(NOT EXISTS "${${f}}")
    message(FATAL_ERROR "gls: ${f} not found: '${${f}}' (apt-get install qflow-tech-osu018 iverilog yosys)")
  endif()
endforeach()
if(NOT ROUND)
  set(ROUND rne)
endif()
if(NOT VECTORS)
  set(VECTORS 200000)
endif()
string(REPLACE "," ";" TAGS "${TAGS}")
set(SEQ_STEPS 4000)
# Three-state cells: no model (abc maps only to the combinational cells, dfflibmap to flops).
set(EXCLUDED_CELLS TBUFX1 TBUFX2)
# Verilator 5.006 mis-evaluates some Yosys gate netlists with its bit-op-tree optimization (the
# netlist of fp_mul e5m10 Stages 2 reports inexact for exact products such as 8 * -3202; there
# Icarus with either cell model set and Verilator with -O0 or -fno-const-bit-op-tree give the
# golden model's answer; upstream verilator/verilator#4059, "Incorrect evaluation of
# combinational circuit with const-bit-op-tree"). -DVERILATOR_GLS_ARGS= (empty) reproduces it:
# the gls.fp_mul_e5m10_s2 flow then fails with flags_o and y_o mismatches.
if(NOT DEFINED VERILATOR_GLS_ARGS)
  set(VERILATOR_GLS_ARGS -fno-const-bit-op-tree)
endif()

string(TIMESTAMP T0 "%s%f")
function(_gls_ms out)
  string(TIMESTAMP t "%s%f")
  math(EXPR ms "(${t} - ${T0}) / 1000")
  set(${out} ${ms} PARENT_SCOPE)
endfunction()

# _gls_run(<step> [DIR <cwd>] [EXPECT_FAIL] COMMAND ...): output into WORK/<step>.log and
# <step>_OUT / <step>_RC in the caller; a non-zero exit stops the test unless EXPECT_FAIL.
function(_gls_run step)
  cmake_parse_arguments(A "EXPECT_FAIL" "DIR" "COMMAND" ${ARGN})
  if(NOT A_DIR)
    set(A_DIR ${WORK})
  endif()
  _gls_ms(t0)
  execute_process(COMMAND ${A_COMMAND} WORKING_DIRECTORY ${A_DIR}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  _gls_ms(t1)
  math(EXPR dt "${t1} - ${t0}")
  file(WRITE ${WORK}/${step}.log "${out}")
  message(STATUS "[gls ${WHAT}] ${step}: exit ${rc}, ${dt} ms  (log ${WORK}/${step}.log)")
  if(NOT A_EXPECT_FAIL AND NOT rc EQUAL 0)
    string(REPLACE ";" " " cmdline "${A_COMMAND}")
    string(LENGTH "${out}" n)
    if(n GREATER 6000)
      math(EXPR s "${n} - 6000")
      string(SUBSTRING "${out}" ${s} -1 out)
    endif()
    message(FATAL_ERROR "gls: step '${step}' failed (exit ${rc}): ${cmdline}\n${out}")
  endif()
  set(${step}_OUT "${out}" PARENT_SCOPE)
  set(${step}_RC "${rc}" PARENT_SCOPE)
endfunction()

function(_gls_fail msg)
  message(FATAL_ERROR "gls ${WHAT}: ${msg}")
endfunction()

# Replaces <from> by <to> in the variable <var>; <from> must occur exactly once.
function(_gls_replace_once var from to what)
  string(FIND "${${var}}" "${from}" p)
  string(FIND "${${var}}" "${from}" q REVERSE)
  if(p LESS 0 OR NOT p EQUAL q)
    _gls_fail("planted error '${what}': '${from}' does not occur exactly once")
  endif()
  string(REPLACE "${from}" "${to}" s "${${var}}")
  set(${var} "${s}" PARENT_SCOPE)
endfunction()

# --- cell models and their check ---------------------------------------------------------------

# Writes the Verilator cell models from the liberty into <out>.
function(_gls_write_models out)
  set(raw ${WORK}/osu018_cells_yosys.v)
  string(REPLACE ";" " " excl "${EXCLUDED_CELLS}")
  file(WRITE ${WORK}/models.ys "read_liberty ${LIB}\ndelete ${excl}\nwrite_verilog -noattr ${raw}\n")
  _gls_run(models COMMAND ${YOSYS} -q -s ${WORK}/models.ys)
  file(READ ${raw} body)
  file(WRITE ${out} "// osu018 cell models for Verilator, written by Yosys (read_liberty without -lib:\n"
    "// the liberty's function/ff/latch groups) from ${LIB}.\n"
    "// Generated by tb/gls/gls_test.cmake (MODE=cells), checked against osu018_stdcells.v with Icarus.\n"
    "// Not modelled: ${excl} (three-state). Do not edit.\n"
    "/* verilator lint_off UNUSEDSIGNAL */\n${body}/* verilator lint_on UNUSEDSIGNAL */\n")
endfunction()

# Checks <models> against the vendor cells with Icarus; sets <out_ok> (TRUE/FALSE) and
# <out_report> (the mismatch lines and the summary) in the caller. <tag> names the log files.
function(_gls_check_models models tag out_ok out_report)
  # The liberty's cells and pins.
  set(json ${WORK}/cells.json)
  file(WRITE ${WORK}/cells_json.ys "read_liberty -lib ${LIB}\nwrite_json ${json}\n")
  _gls_run(cells_json_${tag} COMMAND ${YOSYS} -q -s ${WORK}/cells_json.ys)
  file(READ ${json} j)
  string(JSON ncells LENGTH "${j}" modules)
  math(EXPR last "${ncells} - 1")
  file(READ ${models} mtext)
  file(READ ${CELLS_V} vtext)
  set(decl "")
  set(body "")
  set(checked "")
  foreach(i RANGE ${last})
    string(JSON cell MEMBER "${j}" modules ${i})
    if(cell IN_LIST EXCLUDED_CELLS)
      if(mtext MATCHES "module ${cell}\\(")
        _gls_fail("${models} models the excluded cell ${cell}")
      endif()
      continue()
    endif()
    if(NOT mtext MATCHES "\nmodule ${cell}\\(")
      _gls_fail("${models} has no model of the liberty cell ${cell}")
    endif()
    if(NOT vtext MATCHES "\nmodule ${cell} \\(")
      _gls_fail("${CELLS_V} has no cell ${cell}")
    endif()
    string(JSON np LENGTH "${j}" modules ${cell} ports)
    math(EXPR plast "${np} - 1")
    set(ins "")
    set(outs "")
    foreach(k RANGE ${plast})
      string(JSON pn MEMBER "${j}" modules ${cell} ports ${k})
      string(JSON pd GET "${j}" modules ${cell} ports ${pn} direction)
      if(pd STREQUAL "input")
        list(APPEND ins ${pn})
      else()
        list(APPEND outs ${pn})
      endif()
    endforeach()
    list(LENGTH ins ni)
    list(LENGTH outs no)
    set(conn "")
    set(k 0)
    foreach(pn ${ins})
      string(APPEND conn ".${pn}(i_${cell}[${k}]), ")
      math(EXPR k "${k} + 1")
    endforeach()
    set(cm "${conn}")
    set(cr "${conn}")
    set(ocat_m "")
    set(ocat_r "")
    foreach(pn ${outs})
      string(APPEND decl "  wire m_${cell}_${pn}, r_${cell}_${pn};\n")
      string(APPEND cm ".${pn}(m_${cell}_${pn}), ")
      string(APPEND cr ".${pn}(r_${cell}_${pn}), ")
      list(APPEND ocat_m m_${cell}_${pn})
      list(APPEND ocat_r r_${cell}_${pn})
    endforeach()
    string(REGEX REPLACE ", $" "" cm "${cm}")
    string(REGEX REPLACE ", $" "" cr "${cr}")
    set(rins ${ins})
    list(REVERSE rins)  # MSB first, as %b prints i_<cell>
    string(REPLACE ";" "," inames "${rins}")
    string(REPLACE ";" "," onames "${outs}")
    string(REPLACE ";" ", " om "${ocat_m}")
    string(REPLACE ";" ", " orr "${ocat_r}")
    string(APPEND decl "  reg [${ni}-1:0] i_${cell};\n  ${cell} m_${cell} (${cm});\n  ref_${cell} r_${cell} (${cr});\n")
    set(cmp "if ({${om}} !== {${orr}}) begin errors = errors + 1; $display(\"MISMATCH %0s {${inames}}=%b (step %0d): model {${onames}}=%b, osu018_stdcells.v %b\", \"${cell}\", i_${cell}, n, {${om}}, {${orr}}); end\n      checks = checks + 1;")
    list(FIND ins CLK clk)
    if(clk LESS 0)
      math(EXPR nv "1 << ${ni}")
      string(APPEND body "    // ${cell}: every input combination\n"
        "    for (n = 0; n < ${nv}; n = n + 1) begin\n      i_${cell} = n; #5;\n      ${cmp}\n    end\n"
        "    $display(\"checked %0s: ${nv} combinations of {${inames}}\", \"${cell}\");\n")
    else()
      # Sequential: single-input toggles from all-zero, compared from the first step at which the
      # vendor model's output is not x (the power-up state is unknown; the Verilog model also
      # treats x->0 at time 0 as a falling edge, the UDP does not). DFFSR: see the header.
      set(guard "1")
      if(cell STREQUAL "DFFSR")
        list(FIND ins R ir)
        list(FIND ins S is)
        set(guard "!(k == ${ir} && !i_${cell}[${ir}] && !i_${cell}[${is}])")
      endif()
      string(APPEND body "    // ${cell}: a random walk of single-input toggles\n"
        "    i_${cell} = 0; #5;\n    skipped = 0; started = 0;\n"
        "    for (n = 0; n < ${SEQ_STEPS}; n = n + 1) begin\n"
        "      k = {$random(seed)} % ${ni};\n"
        "      if (${guard}) begin\n        i_${cell}[k] = ~i_${cell}[k]; #5;\n"
        "        if (^{${orr}} !== 1'bx) started = 1;\n"
        "        if (started) begin\n      ${cmp}\n        end\n"
        "      end else skipped = skipped + 1;\n"
        "    end\n"
        "    if (!started) begin errors = errors + 1; $display(\"MISMATCH %0s: the reference output never left x\", \"${cell}\"); end\n"
        "    $display(\"checked %0s: ${SEQ_STEPS} steps (%0d skipped) of {${inames}}\", \"${cell}\", skipped);\n")
    endif()
    list(APPEND checked ${cell})
  endforeach()
  list(LENGTH checked nchecked)
  file(WRITE ${WORK}/cellcheck_${tag}.v "// Generated by tb/gls/gls_test.cmake: every osu018 cell model against osu018_stdcells.v.
`timescale 1ns/10ps
module cellcheck;
  integer n, k, errors, checks, skipped, started, seed;
${decl}
  initial begin
    errors = 0; checks = 0; seed = 1;
${body}
    $display(\"cellcheck: ${nchecked} cells, %0d comparisons, %0d mismatches\", checks, errors);
    $finish;
  end
endmodule
")
  # The vendor cells with their module names prefixed (the UDPs keep theirs).
  string(REGEX REPLACE "\nmodule ([A-Za-z0-9_]+) \\(" "\nmodule ref_\\1 (" vref "${vtext}")
  file(WRITE ${WORK}/osu018_stdcells_ref.v "${vref}")
  _gls_run(iverilog_${tag} COMMAND ${IVERILOG} -o ${WORK}/cellcheck_${tag}.vvp
    ${WORK}/cellcheck_${tag}.v ${WORK}/osu018_stdcells_ref.v ${models})
  _gls_run(vvp_${tag} COMMAND ${VVP} -n ${WORK}/cellcheck_${tag}.vvp)
  set(o "${vvp_${tag}_OUT}")
  string(REGEX MATCHALL "MISMATCH[^\n]*" mm "${o}")
  string(REGEX MATCH "cellcheck: [^\n]*" summary "${o}")
  set(ok FALSE)
  if(summary MATCHES ", 0 mismatches$" AND NOT mm)
    set(ok TRUE)
  elseif(NOT summary)
    _gls_fail("the Icarus cell check did not finish (${WORK}/vvp_${tag}.log)")
  endif()
  list(LENGTH mm nmm)
  if(nmm GREATER 20)
    list(SUBLIST mm 0 20 mm)
    list(APPEND mm "...")
  endif()
  string(REPLACE ";" "\n" mm "${mm}")
  set(${out_ok} ${ok} PARENT_SCOPE)
  set(${out_report} "${mm}\n${summary}" PARENT_SCOPE)
  set(CHECKED_CELLS "${checked}" PARENT_SCOPE)
endfunction()

# --- netlist ------------------------------------------------------------------------------------

# rayunits gen + the flow's mapping script; sets NETLIST_DIR (the generated module) in the caller.
function(_gls_map dir)
  file(REMOVE_RECURSE ${dir})
  _gls_run(gen COMMAND ${RAYUNITS} gen ${UNIT} --format ${FORMAT} --stages ${STAGES}
    --round ${ROUND} --out ${dir} --no-synth)
  # The synthesis flow itself maps the unit (one mapping script: flow.cpp's cell_premap_script
  # and cell_map_script), at a 2 ns target; --netlist writes the mapped unit module alone.
  _gls_run(synth COMMAND ${RAYUNITS} synth ${UNIT} --format ${FORMAT} --stages ${STAGES}
    --round ${ROUND} --flow osu018 --clock 2ns --netlist ${WORK}/netlist.v --json ${WORK}/synth.jsonl)
endfunction()

# Checks the netlist's cells (see the header); sets CELL_SUMMARY in the caller.
function(_gls_check_netlist netlist models)
  file(READ ${netlist} n)
  file(READ ${models} m)
  string(REGEX MATCHALL "\n  [A-Za-z_][A-Za-z0-9_]* [^ \n(]+ \\(" insts "${n}")
  set(types "")
  foreach(i ${insts})
    string(REGEX MATCH "\n  ([A-Za-z_][A-Za-z0-9_]*) " _ "${i}")
    list(APPEND types ${CMAKE_MATCH_1})
  endforeach()
  list(LENGTH types total)
  if(total EQUAL 0)
    _gls_fail("${netlist} has no cell instances")
  endif()
  set(uniq ${types})
  list(REMOVE_DUPLICATES uniq)
  list(SORT uniq)
  set(summary "")
  foreach(t ${uniq})
    if(t IN_LIST EXCLUDED_CELLS)
      _gls_fail("the netlist uses ${t}, which has no model (three-state)")
    endif()
    if(NOT m MATCHES "\nmodule ${t}\\(")
      _gls_fail("the netlist uses ${t}, which is not an osu018 cell model")
    endif()
    set(c ${types})
    list(FILTER c INCLUDE REGEX "^${t}$")
    list(LENGTH c k)
    string(APPEND summary "${t} ${k}, ")
  endforeach()
  # DFFSR: R or S tied to 1 (the corner the cell check skips cannot occur).
  string(REGEX MATCHALL "\n  DFFSR [^;]*;" dffsr "${n}")
  foreach(d ${dffsr})
    if(NOT d MATCHES "\\.R\\(1'h1\\)" AND NOT d MATCHES "\\.S\\(1'h1\\)")
      _gls_fail("a DFFSR with both R and S driven (the cell check does not cover that):${d}")
    endif()
  endforeach()
  string(REGEX REPLACE ", $" "" summary "${summary}")
  set(CELL_SUMMARY "${total} cells: ${summary}" PARENT_SCOPE)
endfunction()

# Verilates <netlist> + <models> and builds <so> (model + port binding from the datasheet).
function(_gls_build_dut tag netlist models so)
  set(obj ${WORK}/obj_${tag})
  set(prefix V${TOP})
  file(REMOVE_RECURSE ${obj})
  _gls_run(verilate_${tag} COMMAND ${VERILATOR} --cc --trace-fst -Wno-fatal -Wno-lint -Wno-style
    --x-assign unique --x-initial unique ${VERILATOR_GLS_ARGS}
    --prefix ${prefix} --top-module ${TOP} -Mdir ${obj} ${netlist} ${models})
  file(READ ${obj}/${prefix}.h hdr)
  string(REGEX MATCHALL "VL_(IN|OUT|INOUT)(8|16|64|W)?\\(&[A-Za-z0-9_]+,[0-9]+,[0-9]+" decls "${hdr}")
  set(model_ports "")
  foreach(d ${decls})
    string(REGEX MATCH "VL_(IN|OUT|INOUT)[0-9W]*\\(&([A-Za-z0-9_]+),([0-9]+),([0-9]+)" _ "${d}")
    string(TOLOWER "${CMAKE_MATCH_1}put" dirn)
    math(EXPR w "${CMAKE_MATCH_3} - ${CMAKE_MATCH_4} + 1")
    list(APPEND model_ports "${CMAKE_MATCH_2}:${dirn}:${w}")
  endforeach()
  file(READ ${NETLIST_DIR}/datasheet.json ds)
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
    _gls_fail("the datasheet's ports (${ds_ports}) are not the netlist's ports (${model_ports})")
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
  _gls_run(compile_${tag} COMMAND ${CXX} -std=c++17 -O1 -fPIC -shared -pthread
    -Wall -Wextra -Werror
    -DVM_TRACE=1 -DVM_TRACE_FST=1 -DVM_TRACE_VCD=0 -DVM_COVERAGE=0 -DVM_SC=0
    -isystem ${obj} -isystem ${VERILATOR_ROOT}/include -isystem ${VERILATOR_ROOT}/include/vltstd
    -I${TB_INCLUDE} ${WORK}/glue_${tag}.cpp -o ${so})
endfunction()

# Runs the FP test plan on <so>; sets <step>_OUT / <step>_RC in the caller.
function(_gls_scoreboard step so filter)
  cmake_parse_arguments(A "EXPECT_FAIL" "" "" ${ARGN})
  set(tagargs "")
  foreach(t ${TAGS})
    list(APPEND tagargs --tag=${t})
  endforeach()
  set(ef "")
  if(A_EXPECT_FAIL)
    set(ef EXPECT_FAIL)
    list(APPEND tagargs --no-trace-on-fail)  # (a planted error: no FST re-run)
  endif()
  _gls_run(${step} ${ef} COMMAND ${LOADER} --dut=${so} --datasheet=${NETLIST_DIR}/datasheet.json
    --config-name=${CONFIG} ${tagargs} --max-errors=5 --vectors=${VECTORS} --gtest_filter=${filter})
  set(${step}_OUT "${${step}_OUT}" PARENT_SCOPE)
  set(${step}_RC "${${step}_RC}" PARENT_SCOPE)
endfunction()

file(MAKE_DIRECTORY ${WORK})

if(MODE STREQUAL "cells")
  set(WHAT osu018_cells)
  _gls_write_models(${WORK}/osu018_cells.v)
  _gls_check_models(${WORK}/osu018_cells.v models ok report)
  if(NOT ok)
    _gls_fail("cell models differ from osu018_stdcells.v:\n${report}")
  endif()
  list(LENGTH CHECKED_CELLS nc)
  string(REGEX MATCH "cellcheck: [^\n]*" summary "${report}")
  _gls_ms(total)
  message(STATUS "[gls ${WHAT}] PASS: ${WORK}/osu018_cells.v: ${summary} (not modelled: ${EXCLUDED_CELLS}); ${total} ms")
  return()
endif()

# netlist / planted
foreach(v UNIT FORMAT STAGES MODELS RAYUNITS LOADER VERILATOR VERILATOR_ROOT CXX TB_INCLUDE GLUE_IN RUGEN)
  if("${${v}}" STREQUAL "")
    message(FATAL_ERROR "gls_test.cmake: -D${v}=... is required for MODE=${MODE}")
  endif()
endforeach()
foreach(f MODELS RAYUNITS LOADER VERILATOR CXX)
  if(NOT EXISTS "${${f}}")
    message(FATAL_ERROR "gls: ${f} not found: '${${f}}' (build tb_gen_loader and rayunits; the "
      "fixture test gls.osu018_cells writes the cell models)")
  endif()
endforeach()
include(${RUGEN})  # ru_gen_top_name(): the wrapper name rule
ru_gen_top_name(TOP UNIT ${UNIT} FORMAT ${FORMAT} STAGES ${STAGES} ROUND ${ROUND})
string(REGEX REPLACE "^ru_${UNIT}_" "gls_" CONFIG "${TOP}")   # gls_e5m10_s2
set(SUITE ${UNIT}_${CONFIG})
set(WHAT ${TOP})
set(NETLIST_DIR ${WORK}/mod)
_gls_map(${NETLIST_DIR})
_gls_check_netlist(${WORK}/netlist.v ${MODELS})
message(STATUS "[gls ${WHAT}] netlist.v: ${CELL_SUMMARY}")

if(MODE STREQUAL "netlist")
  _gls_build_dut(dut ${WORK}/netlist.v ${MODELS} ${WORK}/libdut.so)
  _gls_scoreboard(scoreboard ${WORK}/libdut.so "-Long_*")
  set(out "${scoreboard_OUT}")
  set(want special random reset inject_bitflip inject_latency_late inject_stale)
  if(STAGES GREATER 0)
    list(APPEND want inject_latency_early)
  endif()
  if("exhaustive" IN_LIST TAGS)
    list(APPEND want exhaustive)
  endif()
  foreach(t ${want})
    if(NOT out MATCHES "\\[       OK \\] ${SUITE}\\.${t} ")
      _gls_fail("the scoreboard run has no passing test ${SUITE}.${t} (${WORK}/scoreboard.log)")
    endif()
  endforeach()
  if(out MATCHES "FAILED")
    _gls_fail("the scoreboard reported a failure (${WORK}/scoreboard.log)")
  endif()
  string(REGEX MATCH "\\[  PASSED  \\] [0-9]+ tests?" passed "${out}")
  string(REGEX MATCH "\\[${SUITE}\\.random\\] seed=[0-9]+: [0-9]+ results checked" nrandom "${out}")
  _gls_ms(total)
  message(STATUS "[gls ${WHAT}] PASS: mapped netlist (${CELL_SUMMARY}) on the scoreboard: ${passed} (${nrandom}); ${total} ms")

elseif(MODE STREQUAL "planted")
  # cellfn: one wrong minterm in the OAI21X1 model (Y = !((A|B)&C), flipped at A=B=C=1).
  file(READ ${MODELS} m)
  string(REGEX MATCH "\nmodule OAI21X1\\([^\n]*\n([^e]|e[^n]|en[^d])*endmodule" cellmod "${m}")
  if(NOT cellmod MATCHES "assign Y = ([^;]+);")
    _gls_fail("planted error 'cellfn': no 'assign Y = ...;' in the OAI21X1 model")
  endif()
  set(rhs "${CMAKE_MATCH_1}")
  set(bad "${cellmod}")
  _gls_replace_once(bad "assign Y = ${rhs};" "assign Y = ${rhs} ^ (A & B & C);  // planted" cellfn)
  _gls_replace_once(m "${cellmod}" "${bad}" cellfn)
  file(WRITE ${WORK}/osu018_cells_cellfn.v "${m}")
  _gls_check_models(${WORK}/osu018_cells_cellfn.v cellfn ok report)
  string(REGEX MATCHALL "MISMATCH[^\n]*" mm "${report}")
  list(LENGTH mm nmm)
  if(ok OR NOT nmm EQUAL 1 OR NOT mm MATCHES "^MISMATCH OAI21X1 \\{C,B,A\\}=111 ")
    _gls_fail("planted 'cellfn': the Icarus cell check did not report exactly OAI21X1 {C,B,A}=111:\n${report}")
  endif()
  message(STATUS "[gls ${WHAT}] planted 'cellfn' caught by the cell check: ${mm}")
  _gls_build_dut(cellfn ${WORK}/netlist.v ${WORK}/osu018_cells_cellfn.v ${WORK}/libdut_cellfn.so)
  _gls_scoreboard(scoreboard_cellfn ${WORK}/libdut_cellfn.so "*.random-Long_*" EXPECT_FAIL)
  set(out "${scoreboard_cellfn_OUT}")
  if(scoreboard_cellfn_RC EQUAL 0 OR NOT out MATCHES "MISMATCH at cycle" OR NOT out MATCHES "<-- differs")
    _gls_fail("planted 'cellfn': the scoreboard did not fail with a data mismatch (${WORK}/scoreboard_cellfn.log)")
  endif()
  string(REGEX MATCH "MISMATCH at cycle [0-9]+" first "${out}")
  message(STATUS "[gls ${WHAT}] planted 'cellfn' caught by the scoreboard: ${first}")

  # gate: the gate driving y_o[0] inverted.
  file(READ ${WORK}/netlist.v n)
  _gls_replace_once(n ".Y(y_o[0])" ".Y(planted_n)" gate)
  string(REGEX MATCH "\n  [A-Z0-9]+ [^ ]+ \\(\n([^;]*)\\.Y\\(planted_n\\)" drv "${n}")
  string(REGEX MATCH "\n  ([A-Z0-9]+) ([^ ]+) \\(" _ "${drv}")
  set(gate "${CMAKE_MATCH_1} ${CMAKE_MATCH_2}")
  _gls_replace_once(n "\nendmodule" "
  wire planted_n;
  INVX1 planted_inv (.A(planted_n), .Y(y_o[0]));  // planted: ${gate} inverted
endmodule" gate)
  file(WRITE ${WORK}/netlist_gate.v "${n}")
  _gls_build_dut(gate ${WORK}/netlist_gate.v ${MODELS} ${WORK}/libdut_gate.so)
  _gls_scoreboard(scoreboard_gate ${WORK}/libdut_gate.so "*.random-Long_*" EXPECT_FAIL)
  set(out "${scoreboard_gate_OUT}")
  if(scoreboard_gate_RC EQUAL 0 OR NOT out MATCHES "y_o: expected [^\n]*<-- differs")
    _gls_fail("planted 'gate': the scoreboard did not fail with a y_o mismatch (${WORK}/scoreboard_gate.log)")
  endif()
  string(REGEX MATCH "MISMATCH at cycle [0-9]+" first "${out}")
  message(STATUS "[gls ${WHAT}] planted 'gate' (${gate} -> y_o[0] inverted) caught by the scoreboard: ${first}")
  _gls_ms(total)
  message(STATUS "[gls ${WHAT}] PASS: every planted error (cellfn, gate) was caught; ${total} ms")
else()
  message(FATAL_ERROR "gls_test.cmake: MODE must be cells, netlist or planted, not '${MODE}'")
endif()
