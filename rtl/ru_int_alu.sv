// ru_int_alu: the thread processors' integer ALU (issue 16: every instruction class of the TRaX
// kernel on a unit with RTL). IntW-bit two's complement operands a_i, b_i:
//
//   op_i | operation | y_o
//   -----|-----------|----------------------------------------------------------------
//   0    | add       | a + b (mod 2^IntW)
//   1    | sub       | a - b (mod 2^IntW)
//   2    | and       | a & b
//   3    | or        | a | b
//   4    | xor       | a ^ b
//   5    | sll       | a << s, s = b mod 2^SW (SW = clog2(IntW)); 0 when s >= IntW
//   6    | srl       | a >> s (logical); 0 when s >= IntW
//   7    | sra       | a >> s (arithmetic); every bit the sign of a when s >= IntW
//   8    | slt       | 1 if a < b as signed integers, else 0
//   9    | sltu      | 1 if a < b as unsigned integers, else 0
//   10   | min       | the smaller of a, b (signed)
//   11   | max       | the larger of a, b (signed)
//   12-15| mov       | a
// The golden model is ru::units::int_alu (model/include/rayunits/units/int_units.hpp).
//
// Parameters: IntW (2..64), Stages (latency in cycles, 0 = combinational). CutSel is internal.
// Fully pipelined: one operation per cycle, out_valid_o = in_valid_i delayed by Stages.
//
// Datapath segments and the cut position after each:
//   seg 0  adder/subtracter (its carry gives the comparisons), shifter, logic  | cut 0
//   seg 1  comparison and min/max select, result mux                            -> y_o
// Stages registers go to the cut position chosen by ru_pipe_pkg (one position: it is used from
// Stages 1). Useful maximum: Stages = 1; registers beyond it are placed at the output.
module ru_int_alu #(
  parameter int unsigned IntW = 32,
  parameter int unsigned Stages = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts
) (
  input  logic            clk_i,
  input  logic            rst_ni,
  input  logic            in_valid_i,
  input  logic [IntW-1:0] a_i,
  input  logic [IntW-1:0] b_i,
  input  logic [3:0]      op_i,
  output logic            out_valid_o,
  output logic [IntW-1:0] y_o
);

  localparam int unsigned NSeg = 2;
  localparam int unsigned SW = (IntW > 2) ? $clog2(IntW) : 1;
  // depth estimates (gate levels): the adder's carry chain dominates seg 0
  localparam logic [ru_pipe_pkg::WW-1:0] DepthW =
      ru_pipe_pkg::put_w(ru_pipe_pkg::put_w('0, 0, 2 * $clog2(IntW) + 2), 1, 4);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(CutSel, DepthW, NSeg, Stages);
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(NSeg);
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (IntW < 2 || IntW > 64) begin : gen_width_check
    $error("ru_int_alu: IntW must be 2..64, got %0d", IntW);
  end
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_int_alu: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end

  // ---- seg 0: add/sub, shifts, logic ---------------------------------------------------------
  // a - b as a + ~b + 1 in IntW + 1 bits: the carry out is a >= b (unsigned)
  logic [IntW:0]   s0_sum, s0_dif;
  logic [SW-1:0]   s0_sh;
  logic [IntW-1:0] s0_sll, s0_srl, s0_sra, s0_log;
  assign s0_sum = {1'b0, a_i} + {1'b0, b_i};
  assign s0_dif = {1'b0, a_i} + {1'b0, ~b_i} + {{IntW{1'b0}}, 1'b1};
  assign s0_sh  = b_i[SW-1:0];
  assign s0_sll = a_i << s0_sh;
  assign s0_srl = a_i >> s0_sh;
  assign s0_sra = IntW'($signed(a_i) >>> s0_sh);
  always_comb begin
    case (op_i)
      4'd2:    s0_log = a_i & b_i;
      4'd3:    s0_log = a_i | b_i;
      4'd4:    s0_log = a_i ^ b_i;
      4'd5:    s0_log = s0_sll;
      4'd6:    s0_log = s0_srl;
      4'd7:    s0_log = s0_sra;
      default: s0_log = a_i;  // 12..15 mov (0, 1, 8..11 take other results)
    endcase
  end

  // ---- cut 0 ---------------------------------------------------------------------------------
  logic            c0_valid, c0_geu, c0_sa, c0_sb;
  logic [IntW-1:0] c0_a, c0_b, c0_sum, c0_dif, c0_log;
  logic [3:0]      c0_op;
  ru_pipe #(.Width(5 * IntW + 4 + 3), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({a_i, b_i, s0_sum[IntW-1:0], s0_dif[IntW-1:0], s0_log, op_i, s0_dif[IntW], a_i[IntW-1], b_i[IntW-1]}),
    .valid_o(c0_valid),
    .data_o ({c0_a, c0_b, c0_sum, c0_dif, c0_log, c0_op, c0_geu, c0_sa, c0_sb})
  );
  logic unused_sum_carry;
  assign unused_sum_carry = s0_sum[IntW];

  // ---- seg 1: comparisons, min/max, result mux --------------------------------------------
  logic ltu, lt;
  assign ltu = ~c0_geu;
  // signed: different signs -> a < b iff a is negative; same signs -> the unsigned order
  assign lt = (c0_sa != c0_sb) ? c0_sa : ltu;
  logic [IntW-1:0] y;
  always_comb begin
    case (c0_op)
      4'd0:    y = c0_sum;
      4'd1:    y = c0_dif;
      4'd8:    y = {{(IntW - 1) {1'b0}}, lt};
      4'd9:    y = {{(IntW - 1) {1'b0}}, ltu};
      4'd10:   y = lt ? c0_a : c0_b;
      4'd11:   y = lt ? c0_b : c0_a;
      default: y = c0_log;
    endcase
  end

  // ---- output registers (Stages beyond the cut) ---------------------------------------------
  ru_pipe #(.Width(IntW), .Depth(OutRegs)) u_out (
    .clk_i, .rst_ni,
    .valid_i(c0_valid),
    .data_i (y),
    .valid_o(out_valid_o),
    .data_o (y_o)
  );

endmodule
