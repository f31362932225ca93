// ru_exact_edge: the exact side path of the exactly-once ray-triangle unit (issue 14 section 1,
// docs/UNITS.md "Exactly-once triangles"): the sign of one edge's volume for the symbolically
// perturbed ray a(eps) = a + (eps, eps^2, eps^3),
//   S(eps) = ((a(eps) - m) x d) . e,  e = q1 - q2,
// i.e. the sign of the first non-zero of S = ((a - m) x d) . e, (d x e).x, (d x e).y, (d x e).z,
// evaluated exactly in integer arithmetic (the model: units::exact_detail::exact_edge_sign, GMP).
//
// Parameters: ExpW (2..8), FracW (1..23), Subnormals (1 gradual underflow, 0: a subnormal operand
// reads as a zero of its sign), DigitW (the multiplier's digit: bits of the second factor per
// cycle). Operands must be finite (the unit sends non-finite operands to a miss before this).
//
// Integers: every finite value of eXmY is an integer multiple of 2^(emin-M) of magnitude < 2^L,
// L = 2^E + M - 2 (normal: {1, fraction} << (biased exponent - 1); subnormal: the fraction). So
// a - m, q1 - q2 and d are integers of L+2 bits (signed), a cross-product term of 2L+3, S of 3L+6
// (docs/UNITS.md derives the bounds); registers here carry a few spare bits (WS, WT, WP below).
//
// Sequence (a small microprogram, one step per state; nothing pipelined, one operation at a time):
//   load     operands captured when in_valid_i && in_ready_o
//   convert  9 cycles: s_c = int(a_c) - int(m_c), e_c = int(q1_c) - int(q2_c), d_c = int(d_c)
//   program  for each component i (j = i+1, k = i+2 mod 3):
//              T = 0; T += s_j d_k; T -= s_k d_j; ACC += T e_i            (ACC = S)
//            ACC != 0: done, sign(ACC); else for each i: T = d_j e_k - d_k e_j, T != 0: done
//            (the tie terms (d x e)_x, _y, _z in that order); all zero: sign 0.
//   multiply A * B (A signed, B signed of WS bits) digit-serially, most significant digit first
//            (Horner: P = (P << DigitW) + A * digit; the first digit is signed): ND cycles, then
//            one cycle adds +-P into T or ACC.
// Latency (in_valid_i accepted to out_valid_o): 1 + 9 + 3 * (2 + 3 (ND + 1)) + 1 cycles without
// tie terms, + 3 (1 + 2 (ND + 1)) + 3 with all three; ND = ceil(WS / DigitW). in_ready_o is high
// only while idle (one edge at a time); out_valid_o is a one-cycle pulse with sign_o (2'b01 +1,
// 2'b11 -1, 2'b00 0).
module ru_exact_edge #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned DigitW = 16,
  parameter int unsigned Plant = 0  // tests only: 1 drops the tie terms, 2 subtracts s_j d_k instead of adding
) (
  input  logic clk_i,
  input  logic rst_ni,
  input  logic in_valid_i,
  output logic in_ready_o,
  input  logic [3*(ExpW+FracW+1)-1:0] a_i,   // {z, y, x}
  input  logic [3*(ExpW+FracW+1)-1:0] d_i,
  input  logic [3*(ExpW+FracW+1)-1:0] m_i,   // the edge's lexicographically smaller end point
  input  logic [3*(ExpW+FracW+1)-1:0] q1_i,  // e = q1 - q2 (the edge's orientation in the triangle)
  input  logic [3*(ExpW+FracW+1)-1:0] q2_i,
  output logic out_valid_o,
  output logic [1:0] sign_o
);
  localparam int unsigned W = ExpW + FracW + 1;
  localparam int unsigned L = (1 << ExpW) + FracW - 2;
  localparam int unsigned WS = L + 3;             // s, e, d
  localparam int unsigned WT = 2 * L + 6;         // T (a cross-product term) and every A operand
  localparam int unsigned ND = (WS + DigitW - 1) / DigitW;
  localparam int unsigned WB = ND * DigitW;       // B, sign-extended to whole digits
  localparam int unsigned WP = WT + WB + 1;       // a product A * B
  localparam int unsigned WACC = WP + 2;          // S (sum of three products)

  // ---- the microprogram (one instruction per pc; operand codes: A 0..2 s_c, 3..5 d_c, 6 T;
  // B 0..2 d_c, 3..5 e_c) -------------------------------------------------------------------
  localparam logic [2:0] OpClr = 3'd0, OpMul = 3'd1, OpChkAcc = 3'd2, OpChkT = 3'd3, OpEnd = 3'd4;
  localparam logic [2:0] AS0 = 3'd0, AS1 = 3'd1, AS2 = 3'd2, AD0 = 3'd3, AD1 = 3'd4, AD2 = 3'd5, AT = 3'd6;
  localparam logic [2:0] BD0 = 3'd0, BD1 = 3'd1, BD2 = 3'd2, BE0 = 3'd3, BE1 = 3'd4, BE2 = 3'd5;
  localparam logic P2 = Plant == 2;  // planted: T -= s_j d_k instead of +=
  logic [4:0] pc_q;
  logic [2:0] op, asel, bsel;
  logic to_acc, neg;  // OpMul: add into ACC (else into T); subtract
  always_comb begin
    {op, asel, bsel, to_acc, neg} = {OpEnd, 3'd0, 3'd0, 1'b0, 1'b0};
    unique case (pc_q)
      // S = sum_i (s_j d_k - s_k d_j) e_i, (i, j, k) = (x, y, z), (y, z, x), (z, x, y)
      5'd0, 5'd4, 5'd8: op = OpClr;
      5'd1: {op, asel, bsel, to_acc, neg} = {OpMul, AS1, BD2, 1'b0, P2};
      5'd2: {op, asel, bsel, to_acc, neg} = {OpMul, AS2, BD1, 1'b0, 1'b1};
      5'd3: {op, asel, bsel, to_acc, neg} = {OpMul, AT, BE0, 1'b1, 1'b0};
      5'd5: {op, asel, bsel, to_acc, neg} = {OpMul, AS2, BD0, 1'b0, P2};
      5'd6: {op, asel, bsel, to_acc, neg} = {OpMul, AS0, BD2, 1'b0, 1'b1};
      5'd7: {op, asel, bsel, to_acc, neg} = {OpMul, AT, BE1, 1'b1, 1'b0};
      5'd9: {op, asel, bsel, to_acc, neg} = {OpMul, AS0, BD1, 1'b0, P2};
      5'd10: {op, asel, bsel, to_acc, neg} = {OpMul, AS1, BD0, 1'b0, 1'b1};
      5'd11: {op, asel, bsel, to_acc, neg} = {OpMul, AT, BE2, 1'b1, 1'b0};
      5'd12: op = OpChkAcc;
      default:
        if (Plant != 1) begin  // the tie terms (d x e)_i = d_j e_k - d_k e_j, i = x, y, z
          unique case (pc_q)
            5'd13, 5'd17, 5'd21: op = OpClr;
            5'd14: {op, asel, bsel, to_acc, neg} = {OpMul, AD1, BE2, 1'b0, 1'b0};
            5'd15: {op, asel, bsel, to_acc, neg} = {OpMul, AD2, BE1, 1'b0, 1'b1};
            5'd18: {op, asel, bsel, to_acc, neg} = {OpMul, AD2, BE0, 1'b0, 1'b0};
            5'd19: {op, asel, bsel, to_acc, neg} = {OpMul, AD0, BE2, 1'b0, 1'b1};
            5'd22: {op, asel, bsel, to_acc, neg} = {OpMul, AD0, BE1, 1'b0, 1'b0};
            5'd23: {op, asel, bsel, to_acc, neg} = {OpMul, AD1, BE0, 1'b0, 1'b1};
            5'd16, 5'd20, 5'd24: op = OpChkT;
            default: op = OpEnd;
          endcase
        end
    endcase
  end

  // ---- format value -> integer in units of 2^(emin - FracW) --------------------------------
  function automatic logic [WS-1:0] to_int(input logic [W-1:0] x);
    logic [ExpW-1:0] be;
    logic [WS-1:0] mag;
    be = x[W-2:FracW];
    if (be == '0) mag = Subnormals != 0 ? WS'(x[FracW-1:0]) : '0;
    else mag = WS'({1'b1, x[FracW-1:0]}) << (be - 1'b1);
    to_int = x[W-1] ? -mag : mag;  // two's complement
  endfunction

  localparam logic [2:0] SIdle = 3'd0, SConv = 3'd1, SExec = 3'd2, SMul = 3'd3, SMulAdd = 3'd4, SDone = 3'd5;
  logic [2:0] state_q;
  logic [3*W-1:0] a_q, d_q, m_q, q1_q, q2_q;  // the operands ({z, y, x} as the ports)
  logic [3*WS-1:0] s_q, e_q, dd_q;             // a - m, q1 - q2, d as integers (two's complement)
  logic signed [WT-1:0] t_q;
  logic signed [WACC-1:0] acc_q;
  logic signed [WP-1:0] p_q;
  logic [WB-1:0] b_q;
  logic [$clog2(ND+1)-1:0] dig_q;
  logic [3:0] cnt_q;
  logic [1:0] sign_q;

  // operand muxes
  logic signed [WT-1:0] a_op;
  logic signed [WS-1:0] b_op;
  always_comb begin
    unique case (asel)
      AS0, AS1, AS2: a_op = WT'($signed(s_q[asel[1:0]*WS +: WS]));
      AD0, AD1, AD2: a_op = WT'($signed(dd_q[2'(asel - AD0)*WS +: WS]));
      default: a_op = t_q;
    endcase
    b_op = bsel < BE0 ? $signed(dd_q[bsel[1:0]*WS +: WS]) : $signed(e_q[2'(bsel - BE0)*WS +: WS]);
  end

  // one Horner step: the current digit (the first one signed, the others unsigned)
  logic signed [DigitW:0] digit;
  logic signed [WT+DigitW:0] pp;
  logic signed [WP-1:0] p_next;
  always_comb begin
    digit = dig_q == '0 ? {b_q[WB-1], b_q[WB-1 -: DigitW]} : {1'b0, b_q[WB-1 -: DigitW]};
    pp = '0;  // a_op * digit as shift-and-add (the top bit of the signed digit weighs -2^DigitW)
    for (int b = 0; b <= DigitW; b++)
      if (digit[b]) pp = b == DigitW ? pp - ((WT+DigitW+1)'(a_op) <<< b) : pp + ((WT+DigitW+1)'(a_op) <<< b);
    p_next = (p_q <<< DigitW) + WP'(pp);
  end

  // conversion step c (0..8): component c % 3 of s (c < 3), e (c < 6), d
  logic [1:0] cc;
  logic [WS-1:0] conv0, conv1;
  always_comb begin
    cc = 2'(cnt_q % 4'd3);
    unique case (cnt_q / 4'd3)
      4'd0: begin conv0 = to_int(a_q[cc*W +: W]); conv1 = to_int(m_q[cc*W +: W]); end
      4'd1: begin conv0 = to_int(q1_q[cc*W +: W]); conv1 = to_int(q2_q[cc*W +: W]); end
      default: begin conv0 = to_int(d_q[cc*W +: W]); conv1 = '0; end
    endcase
  end

  assign in_ready_o = state_q == SIdle;
  assign out_valid_o = state_q == SDone;
  assign sign_o = sign_q;

  // control (reset): the state, the program counter and the step counters
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      state_q <= SIdle;
      pc_q <= '0;
      cnt_q <= '0;
      dig_q <= '0;
    end else begin
      unique case (state_q)
        SIdle: if (in_valid_i) begin
          cnt_q <= '0;
          state_q <= SConv;
        end
        SConv: begin
          cnt_q <= cnt_q + 1'b1;
          if (cnt_q == 4'd8) begin
            pc_q <= '0;
            state_q <= SExec;
          end
        end
        SExec: begin
          unique case (op)
            OpMul: begin
              dig_q <= '0;
              state_q <= SMul;
            end
            OpChkAcc: begin
              if (acc_q != '0) state_q <= SDone;
              pc_q <= pc_q + 1'b1;
            end
            OpChkT: begin
              if (t_q != '0) state_q <= SDone;
              pc_q <= pc_q + 1'b1;
            end
            OpEnd: state_q <= SDone;  // every term zero
            default: pc_q <= pc_q + 1'b1;  // OpClr
          endcase
        end
        SMul: begin
          dig_q <= dig_q + 1'b1;
          if (32'(dig_q) == ND - 1) state_q <= SMulAdd;
        end
        SMulAdd: begin
          pc_q <= pc_q + 1'b1;
          state_q <= SExec;
        end
        default: state_q <= SIdle;  // SDone: the result was shown for one cycle
      endcase
    end
  end

  // datapath (no reset: every register is written before it is read in a test)
  always_ff @(posedge clk_i) begin
    unique case (state_q)
      SIdle: if (in_valid_i) begin
        a_q <= a_i;
        d_q <= d_i;
        m_q <= m_i;
        q1_q <= q1_i;
        q2_q <= q2_i;
      end
      SConv: begin
        unique case (cnt_q / 4'd3)
          4'd0: s_q[cc*WS +: WS] <= WS'(conv0 - conv1);
          4'd1: e_q[cc*WS +: WS] <= WS'(conv0 - conv1);
          default: dd_q[cc*WS +: WS] <= WS'(conv0);
        endcase
        if (cnt_q == 4'd8) acc_q <= '0;
      end
      SExec: begin
        unique case (op)
          OpClr: t_q <= '0;
          OpMul: begin
            b_q <= {{(WB-WS){b_op[WS-1]}}, b_op};
            p_q <= '0;
          end
          OpChkAcc: sign_q <= acc_q < 0 ? 2'b11 : 2'b01;
          OpChkT: sign_q <= t_q < 0 ? 2'b11 : 2'b01;
          default: sign_q <= 2'b00;  // OpEnd
        endcase
      end
      SMul: begin
        p_q <= p_next;
        b_q <= b_q << DigitW;
      end
      SMulAdd: begin
        if (to_acc) acc_q <= neg ? acc_q - WACC'(p_q) : acc_q + WACC'(p_q);
        else t_q <= neg ? t_q - WT'(p_q) : t_q + WT'(p_q);
      end
      default: ;
    endcase
  end
endmodule
