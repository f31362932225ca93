// ru_branch: the thread processors' branch unit (issue 16): compares two IntW-bit registers and
// computes the next PcW-bit program counter.
//
//   op_i | taken_o when        | op_i | taken_o when
//   -----|---------------------|------|-------------------------------
//   0    | a == b   (beq)      | 4    | a < b unsigned   (bltu)
//   1    | a != b   (bne)      | 5    | a >= b unsigned  (bgeu)
//   2    | a < b signed  (blt) | 6, 7 | always (jump)
//   3    | a >= b signed (bge) |      |
//   y_o = taken_o ? pc_i + off_i : pc_i + 1 (mod 2^PcW; off_i two's complement, in instructions)
// The golden model is ru::units::branch (model/include/rayunits/units/int_units.hpp). The TRaX
// kernel's branches on a predicate register p are bne p, 0.
//
// Parameters: IntW (2..64), PcW (2..64), Stages (latency, 0 = combinational). CutSel is
// internal. Fully pipelined: out_valid_o = in_valid_i delayed by Stages.
//
// Datapath segments and the cut position after each:
//   seg 0  a - b (carry and zero), pc + off, pc + 1          | cut 0
//   seg 1  condition select, next-pc mux                      -> taken_o, y_o
// Useful maximum: Stages = 1; registers beyond it are placed at the output.
module ru_branch #(
  parameter int unsigned IntW = 32,
  parameter int unsigned PcW = 32,
  parameter int unsigned Stages = 0,
  parameter logic [ru_pipe_pkg::MaxSeg:0] CutSel = ru_pipe_pkg::AutoCuts
) (
  input  logic            clk_i,
  input  logic            rst_ni,
  input  logic            in_valid_i,
  input  logic [IntW-1:0] a_i,
  input  logic [IntW-1:0] b_i,
  input  logic [PcW-1:0]  pc_i,
  input  logic [PcW-1:0]  off_i,
  input  logic [2:0]      op_i,
  output logic            out_valid_o,
  output logic            taken_o,
  output logic [PcW-1:0]  y_o
);

  localparam int unsigned NSeg = 2;
  localparam logic [ru_pipe_pkg::WW-1:0] DepthW =
      ru_pipe_pkg::put_w(ru_pipe_pkg::put_w('0, 0, 2 * $clog2(IntW > PcW ? IntW : PcW) + 2), 1, 3);
  localparam logic [ru_pipe_pkg::MaxSeg:0] Cuts = ru_pipe_pkg::sel_mask(CutSel, DepthW, NSeg, Stages);
  localparam int unsigned MaxUsefulStages = ru_pipe_pkg::max_useful(NSeg);
  localparam int unsigned OutRegs = ru_pipe_pkg::out_regs(Cuts, Stages);
  if (IntW < 2 || IntW > 64 || PcW < 2 || PcW > 64) begin : gen_width_check
    $error("ru_branch: IntW and PcW must be 2..64, got %0d and %0d", IntW, PcW);
  end
  if (CutSel[ru_pipe_pkg::MaxSeg] &&
      OutRegs != ru_pipe_pkg::extra_regs(Stages, MaxUsefulStages)) begin : gen_out_check
    $error("ru_branch: internal error: %0d output registers at Stages %0d", OutRegs, Stages);
  end

  // ---- seg 0 ---------------------------------------------------------------------------------
  logic [IntW:0]  s0_dif;
  logic [PcW-1:0] s0_target, s0_next;
  assign s0_dif    = {1'b0, a_i} + {1'b0, ~b_i} + {{IntW{1'b0}}, 1'b1};  // carry = a >= b unsigned
  assign s0_target = pc_i + off_i;
  assign s0_next   = pc_i + {{(PcW - 1) {1'b0}}, 1'b1};

  // ---- cut 0 ---------------------------------------------------------------------------------
  logic           c0_valid, c0_geu, c0_eq, c0_sa, c0_sb;
  logic [PcW-1:0] c0_target, c0_next;
  logic [2:0]     c0_op;
  ru_pipe #(.Width(2 * PcW + 3 + 4), .Depth(Cuts[0] ? 1 : 0)) u_cut0 (
    .clk_i, .rst_ni,
    .valid_i(in_valid_i),
    .data_i ({s0_target, s0_next, op_i, s0_dif[IntW], (s0_dif[IntW-1:0] == '0), a_i[IntW-1], b_i[IntW-1]}),
    .valid_o(c0_valid),
    .data_o ({c0_target, c0_next, c0_op, c0_geu, c0_eq, c0_sa, c0_sb})
  );

  // ---- seg 1 ---------------------------------------------------------------------------------
  logic lt, taken;
  assign lt = (c0_sa != c0_sb) ? c0_sa : ~c0_geu;
  always_comb begin
    case (c0_op)
      3'd0:    taken = c0_eq;
      3'd1:    taken = ~c0_eq;
      3'd2:    taken = lt;
      3'd3:    taken = ~lt;
      3'd4:    taken = ~c0_geu;
      3'd5:    taken = c0_geu;
      default: taken = 1'b1;
    endcase
  end

  // ---- output registers ----------------------------------------------------------------------
  ru_pipe #(.Width(1 + PcW), .Depth(OutRegs)) u_out (
    .clk_i, .rst_ni,
    .valid_i(c0_valid),
    .data_i ({taken, taken ? c0_target : c0_next}),
    .valid_o(out_valid_o),
    .data_o ({taken_o, y_o})
  );

endmodule
