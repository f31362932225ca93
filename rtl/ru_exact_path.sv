// ru_exact_path: the exact side path of the exactly-once ray-triangle unit (issue 14 section 1,
// docs/UNITS.md "Exactly-once triangles"). One request at a time, either
//   op_i = k (0..2)  the sign of edge k's volume for the symbolically perturbed ray
//                    a(eps) = a + (eps, eps^2, eps^3): S(eps) = ((a(eps) - m) x d) . e,
//                    e = q1 - q2 with q1 = p_{k+1}, q2 = p_{k+2} (indices mod 3), m = the
//                    lexicographically smaller of q1, q2 (Kensler 3.10); i.e. the sign of the first
//                    non-zero of S = ((a - m) x d) . e, (d x e).x, (d x e).y, (d x e).z
//                    (model: units::exact_detail::exact_edge_sign)
//   op_i = 3         the exact interval test t_min < Va / V < t_max, n = (p2 - p0) x (p1 - p2),
//                    V = n . d, Va = n . (p2 - a); false when V = 0 or t_min / t_max is NaN; an
//                    infinite bound compares by its sign (model: exact_detail::exact_interval)
// evaluated exactly in integer arithmetic. res_o: edge 2'b01 +1, 2'b11 -1, 2'b00 0; interval
// 2'b01 inside, 2'b00 not.
//
// Parameters: ExpW (2..8), FracW (1..23), Subnormals (1 gradual underflow, 0: a subnormal operand
// reads as a zero of its sign), DigitW (bits of the multiplier's second factor per cycle), Plant
// (tests only: 1 drops the tie terms, 2 adds s_k d_j instead of subtracting it, 3 makes the
// interval's lower bound inclusive). a, d, p0..p2 must be finite (the unit sends non-finite
// operands to a miss before this).
//
// Integers: every finite value of eXmY is an integer multiple of u = 2^(emin-M) of magnitude
// < 2^L, L = 2^E + M - 2 (normal: {1, fraction} << (biased exponent - 1); subnormal: the
// fraction). Differences of two values are L+2 bits (signed; registers R, WS = L+3), a
// cross-product term 2L+3 (T, WT = 2L+6), S, V, Va 3L+6 (ACC, ACC2, WACC = 3L+8), and with
// t = T_t u = T_t / 2^K (K = M - emin) the interval test compares Va 2^K with T_t V:
// X = Va 2^K - T_t V, |X| < 2^(4L+6) (WX = 4L+10). docs/UNITS.md derives the bounds.
//
// Sequence: the request's operands are captured when in_valid_i && in_ready_o; a microprogram
// (edge: pc 0.., interval: pc 64..; one instruction at a time) converts them into the register
// file R (one converter), forms differences (one subtractor), and multiplies digit-serially:
// DST +-= A * B with A in R, T or ACC2 and B in R, most significant digit of B first (Horner:
// P = (P << DigitW) + A * digit, the first digit signed; shift-and-add, no `*`): ND =
// ceil(WS / DigitW) cycles, then one cycle adds +-P into T, ACC, ACC2 or X.
// Latency (accepting edge to the edge after which out_valid_o is high; every instruction one
// cycle, a multiplication ND + 2):
//   edge      9 ND + 41 when S != 0; + 2 ND + 6 per tie term looked at; + 1 when all are zero
//   interval  18 ND + 69 when V = 0, else 20 ND + 77
// in_ready_o is high only while idle; out_valid_o is a one-cycle pulse.
module ru_exact_path #(
  parameter int unsigned ExpW = 8,
  parameter int unsigned FracW = 23,
  parameter int unsigned Subnormals = 1,
  parameter int unsigned DigitW = 16,
  parameter int unsigned Plant = 0
) (
  input  logic clk_i,
  input  logic rst_ni,
  input  logic in_valid_i,
  output logic in_ready_o,
  input  logic [1:0] op_i,
  input  logic [3*(ExpW+FracW+1)-1:0] a_i,   // {z, y, x}
  input  logic [3*(ExpW+FracW+1)-1:0] d_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p0_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p1_i,
  input  logic [3*(ExpW+FracW+1)-1:0] p2_i,
  input  logic [ExpW+FracW:0] tmin_i,
  input  logic [ExpW+FracW:0] tmax_i,
  output logic out_valid_o,
  output logic [1:0] res_o
);
  localparam int unsigned W = ExpW + FracW + 1;
  localparam int unsigned L = (1 << ExpW) + FracW - 2;
  localparam int unsigned K = FracW + (1 << (ExpW - 1)) - 2;  // t = T_t / 2^K
  localparam int unsigned WS = L + 3;
  localparam int unsigned WT = 2 * L + 6;
  localparam int unsigned WACC = 3 * L + 8;
  localparam int unsigned WX = 4 * L + 10;
  localparam int unsigned ND = (WS + DigitW - 1) / DigitW;
  localparam int unsigned WB = ND * DigitW;       // B, sign-extended to whole digits
  localparam int unsigned WP = WACC + WB + 1;     // a product A * B
  localparam int unsigned NR = 17;                // register file entries (WS bits each)

  // ---- the microprogram --------------------------------------------------------------------
  // f1, f2, f3: 5-bit fields. CONV R[f1] = int(operand f2) (f2 0..16: a.xyz d.xyz p0 p1 p2 tmin
  // tmax; 17..19 q1.xyz, 20..22 q2.xyz of the requested edge); SUB R[f1] = R[f2] - R[f3]; LEX
  // lex = (q1 is the smaller: the first non-zero of E = R[12..14] negative, or none); SUBM
  // R[f1] = R[f2] - (lex ? R[6+f3] : R[9+f3]); MUL dst +-= A[f1] * R[f2] (A: 0..16 R, 17 T,
  // 18 ACC2; dst 0 T, 1 ACC, 2 ACC2, 3 X); CHKACC / CHKT: done with the sign if non-zero; CHKV:
  // done (outside) if V = 0; LDX X = ACC << K; SGNLO keeps sign(X); FIN decides the interval.
  localparam logic [3:0] OClr = 4'd0, OConv = 4'd1, OSub = 4'd2, OLex = 4'd3, OSubM = 4'd4, OMul = 4'd5,
                         OChkAcc = 4'd6, OChkT = 4'd7, OChkV = 4'd8, OLdX = 4'd9, OSgnLo = 4'd10,
                         OFin = 4'd11, OEnd = 4'd12;
  localparam logic [4:0] AT = 5'd17, AV = 5'd18;
  localparam logic [1:0] DT = 2'd0, DAcc = 2'd1, DV = 2'd2, DX = 2'd3;
  localparam logic P2 = Plant == 2;
  logic [6:0] pc_q;
  logic [3:0] op;
  logic [4:0] f1, f2, f3;
  logic [1:0] dst;
  logic neg;
  // register file map: edge  r0-2 a -> s = a - m, r3-5 d, r6-8 q1, r9-11 q2, r12-14 e = q1 - q2
  //                    interval r0-2 a -> f = p2 - a, r3-5 d, r6-8 p0 -> e1 = p2 - p0,
  //                             r9-11 p1 -> e0 = p1 - p2, r12-14 p2, r15 tmin, r16 tmax
  always_comb begin
    {op, f1, f2, f3, dst, neg} = {OEnd, 5'd0, 5'd0, 5'd0, DT, 1'b0};
    if (pc_q < 7'd12) begin  // convert a, d, q1, q2
      op = OConv;
      f1 = 5'(pc_q);
      f2 = pc_q < 7'd6 ? 5'(pc_q) : 5'(pc_q + 7'd11);
    end else if (pc_q < 7'd15) begin  // e = q1 - q2
      {op, f1, f2, f3} = {OSub, 5'(pc_q), 5'(pc_q - 7'd6), 5'(pc_q - 7'd3)};
    end else if (pc_q == 7'd15) begin
      op = OLex;
    end else if (pc_q < 7'd19) begin  // s = a - m
      {op, f1, f2, f3} = {OSubM, 5'(pc_q - 7'd16), 5'(pc_q - 7'd16), 5'(pc_q - 7'd16)};
    end else if (pc_q >= 7'd64 && pc_q < 7'd81) begin  // interval: convert all 17 operands
      {op, f1, f2} = {OConv, 5'(pc_q - 7'd64), 5'(pc_q - 7'd64)};
    end else if (pc_q >= 7'd81 && pc_q < 7'd84) begin  // f = p2 - a
      {op, f1, f2, f3} = {OSub, 5'(pc_q - 7'd81), 5'(pc_q - 7'd69), 5'(pc_q - 7'd81)};
    end else if (pc_q >= 7'd84 && pc_q < 7'd87) begin  // e1 = p2 - p0
      {op, f1, f2, f3} = {OSub, 5'(pc_q - 7'd78), 5'(pc_q - 7'd72), 5'(pc_q - 7'd78)};
    end else if (pc_q >= 7'd87 && pc_q < 7'd90) begin  // e0 = p1 - p2
      {op, f1, f2, f3} = {OSub, 5'(pc_q - 7'd78), 5'(pc_q - 7'd78), 5'(pc_q - 7'd75)};
    end else begin
      unique case (pc_q)
        // S = sum_i (s_j d_k - s_k d_j) e_i, (i, j, k) = (x, y, z), (y, z, x), (z, x, y)
        7'd19, 7'd23, 7'd27: op = OClr;
        7'd20: {op, f1, f2, dst, neg} = {OMul, 5'd1, 5'd5, DT, 1'b0};
        7'd21: {op, f1, f2, dst, neg} = {OMul, 5'd2, 5'd4, DT, ~P2};
        7'd22: {op, f1, f2, dst, neg} = {OMul, AT, 5'd12, DAcc, 1'b0};
        7'd24: {op, f1, f2, dst, neg} = {OMul, 5'd2, 5'd3, DT, 1'b0};
        7'd25: {op, f1, f2, dst, neg} = {OMul, 5'd0, 5'd5, DT, ~P2};
        7'd26: {op, f1, f2, dst, neg} = {OMul, AT, 5'd13, DAcc, 1'b0};
        7'd28: {op, f1, f2, dst, neg} = {OMul, 5'd0, 5'd4, DT, 1'b0};
        7'd29: {op, f1, f2, dst, neg} = {OMul, 5'd1, 5'd3, DT, ~P2};
        7'd30: {op, f1, f2, dst, neg} = {OMul, AT, 5'd14, DAcc, 1'b0};
        7'd31: op = OChkAcc;
        // the tie terms (d x e)_i = d_j e_k - d_k e_j, i = x, y, z (Plant 1: none)
        7'd32, 7'd36, 7'd40: op = Plant == 1 ? OEnd : OClr;
        7'd33: {op, f1, f2, dst, neg} = {OMul, 5'd4, 5'd14, DT, 1'b0};
        7'd34: {op, f1, f2, dst, neg} = {OMul, 5'd5, 5'd13, DT, 1'b1};
        7'd37: {op, f1, f2, dst, neg} = {OMul, 5'd5, 5'd12, DT, 1'b0};
        7'd38: {op, f1, f2, dst, neg} = {OMul, 5'd3, 5'd14, DT, 1'b1};
        7'd41: {op, f1, f2, dst, neg} = {OMul, 5'd3, 5'd13, DT, 1'b0};
        7'd42: {op, f1, f2, dst, neg} = {OMul, 5'd4, 5'd12, DT, 1'b1};
        7'd35, 7'd39, 7'd43: op = OChkT;
        // interval: n_i = e1_j e0_k - e1_k e0_j; V = n . d (ACC2), Va = n . f (ACC)
        7'd90, 7'd94, 7'd98, 7'd102, 7'd106, 7'd110: op = OClr;
        7'd91, 7'd103: {op, f1, f2, dst, neg} = {OMul, 5'd7, 5'd11, DT, 1'b0};
        7'd92, 7'd104: {op, f1, f2, dst, neg} = {OMul, 5'd8, 5'd10, DT, 1'b1};
        7'd95, 7'd107: {op, f1, f2, dst, neg} = {OMul, 5'd8, 5'd9, DT, 1'b0};
        7'd96, 7'd108: {op, f1, f2, dst, neg} = {OMul, 5'd6, 5'd11, DT, 1'b1};
        7'd99, 7'd111: {op, f1, f2, dst, neg} = {OMul, 5'd6, 5'd10, DT, 1'b0};
        7'd100, 7'd112: {op, f1, f2, dst, neg} = {OMul, 5'd7, 5'd9, DT, 1'b1};
        7'd93: {op, f1, f2, dst, neg} = {OMul, AT, 5'd3, DV, 1'b0};
        7'd97: {op, f1, f2, dst, neg} = {OMul, AT, 5'd4, DV, 1'b0};
        7'd101: {op, f1, f2, dst, neg} = {OMul, AT, 5'd5, DV, 1'b0};
        7'd105: {op, f1, f2, dst, neg} = {OMul, AT, 5'd0, DAcc, 1'b0};
        7'd109: {op, f1, f2, dst, neg} = {OMul, AT, 5'd1, DAcc, 1'b0};
        7'd113: {op, f1, f2, dst, neg} = {OMul, AT, 5'd2, DAcc, 1'b0};
        7'd114: op = OChkV;
        // X = Va 2^K - T_t V for t_min, then t_max
        7'd115, 7'd118: op = OLdX;
        7'd116: {op, f1, f2, dst, neg} = {OMul, AV, 5'd15, DX, 1'b1};
        7'd119: {op, f1, f2, dst, neg} = {OMul, AV, 5'd16, DX, 1'b1};
        7'd117: op = OSgnLo;
        7'd120: op = OFin;
        default: op = OEnd;
      endcase
    end
  end

  // ---- format value -> integer in units of 2^(emin - FracW) (two's complement) ---------------
  function automatic logic [WS-1:0] to_int(input logic [W-1:0] x);
    logic [ExpW-1:0] be;
    logic [WS-1:0] mag;
    be = x[W-2:FracW];
    if (be == '0) mag = Subnormals != 0 ? WS'(x[FracW-1:0]) : '0;
    else mag = WS'({1'b1, x[FracW-1:0]}) << (be - 1'b1);
    to_int = x[W-1] ? -mag : mag;
  endfunction

  localparam logic [2:0] SIdle = 3'd0, SExec = 3'd1, SMul = 3'd2, SMulAdd = 3'd3, SDone = 3'd4;
  logic [2:0] state_q;
  logic [1:0] op_q;
  logic [17*W-1:0] raw_q;        // a.xyz d.xyz p0.xyz p1.xyz p2.xyz tmin tmax
  logic [NR*WS-1:0] r_q;
  logic signed [WT-1:0] t_q;
  logic signed [WACC-1:0] acc_q, acc2_q;
  logic signed [WX-1:0] x_q;
  logic signed [WP-1:0] p_q;
  logic [WB-1:0] b_q;
  logic [$clog2(ND+1)-1:0] dig_q;
  logic lex_q;
  logic [1:0] lo_q, res_q;

  // operand muxes
  logic signed [WS-1:0] r1, r2, r3, rm;
  logic signed [WACC-1:0] a_op;
  always_comb begin
    r1 = $signed(r_q[f1*WS +: WS]);
    r2 = $signed(r_q[f2*WS +: WS]);
    r3 = $signed(r_q[f3*WS +: WS]);
    rm = $signed(r_q[(lex_q ? 6 : 9) * WS + 32'(f3) * WS +: WS]);
    unique case (f1)
      AT: a_op = WACC'(t_q);
      AV: a_op = acc2_q;
      default: a_op = WACC'(r1);
    endcase
  end

  // the converter: operand f2 (17..22: q1 / q2 of the requested edge)
  logic [4:0] src;
  logic [W-1:0] conv_in;
  always_comb begin
    if (f2 >= 5'd20) src = 5'd6 + 5'd3 * ((5'(op_q) + 5'd2) % 5'd3) + (f2 - 5'd20);
    else if (f2 >= 5'd17) src = 5'd6 + 5'd3 * ((5'(op_q) + 5'd1) % 5'd3) + (f2 - 5'd17);
    else src = f2;
    conv_in = raw_q[src*W +: W];
  end

  // one Horner step: the current digit (the first one signed, the others unsigned)
  logic signed [DigitW:0] digit;
  logic signed [WACC+DigitW:0] pp;
  logic signed [WP-1:0] p_next;
  always_comb begin
    digit = dig_q == '0 ? {b_q[WB-1], b_q[WB-1 -: DigitW]} : {1'b0, b_q[WB-1 -: DigitW]};
    pp = '0;  // a_op * digit as shift-and-add (the top bit of the signed digit weighs -2^DigitW)
    for (int b = 0; b <= DigitW; b++)
      if (digit[b])
        pp = b == DigitW ? pp - ((WACC+DigitW+1)'(a_op) <<< b) : pp + ((WACC+DigitW+1)'(a_op) <<< b);
    p_next = (p_q <<< DigitW) + WP'(pp);
  end

  // the interval decision from sign(X) at t_min (lo_q), sign(X) at t_max (x_q) and sign(V)
  logic tmin_nan, tmax_nan, tmin_inf, tmax_inf, above, below, v_neg, in_range;
  always_comb begin
    tmin_inf = raw_q[15*W+FracW +: ExpW] == '1;
    tmax_inf = raw_q[16*W+FracW +: ExpW] == '1;
    tmin_nan = tmin_inf && raw_q[15*W +: FracW] != '0;
    tmax_nan = tmax_inf && raw_q[16*W +: FracW] != '0;
    v_neg = acc2_q < 0;
    // t > t_min <=> X(t_min) has V's sign; t < t_max <=> X(t_max) has the opposite sign
    if (tmin_inf) above = raw_q[16*W-1];
    else if (Plant == 3 && lo_q == 2'b00) above = 1'b1;
    else above = lo_q != 2'b00 && (lo_q == 2'b11) == v_neg;
    if (tmax_inf) below = !raw_q[17*W-1];
    else below = x_q != '0 && (x_q < 0) != v_neg;
    in_range = !tmin_nan && !tmax_nan && above && below;
  end

  assign in_ready_o = state_q == SIdle;
  assign out_valid_o = state_q == SDone;
  assign res_o = res_q;

  // control (reset): the state, the program counter, the digit counter
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      state_q <= SIdle;
      pc_q <= '0;
      dig_q <= '0;
    end else begin
      unique case (state_q)
        SIdle: if (in_valid_i) begin
          pc_q <= op_i == 2'd3 ? 7'd64 : 7'd0;
          state_q <= SExec;
        end
        SExec: begin
          unique case (op)
            OMul: begin
              dig_q <= '0;
              state_q <= SMul;
            end
            OChkAcc: begin
              if (acc_q != '0) state_q <= SDone;
              pc_q <= pc_q + 1'b1;
            end
            OChkT: begin
              if (t_q != '0) state_q <= SDone;
              pc_q <= pc_q + 1'b1;
            end
            OChkV: begin
              if (acc2_q == '0) state_q <= SDone;
              pc_q <= pc_q + 1'b1;
            end
            OFin, OEnd: state_q <= SDone;
            default: pc_q <= pc_q + 1'b1;
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

  // datapath (no reset: every register is written before a request reads it)
  always_ff @(posedge clk_i) begin
    unique case (state_q)
      SIdle: if (in_valid_i) begin
        op_q <= op_i;
        raw_q <= {tmax_i, tmin_i, p2_i, p1_i, p0_i, d_i, a_i};
        acc_q <= '0;
        acc2_q <= '0;
      end
      SExec: begin
        unique case (op)
          OConv: r_q[f1*WS +: WS] <= to_int(conv_in);
          OSub: r_q[f1*WS +: WS] <= WS'(r2 - r3);
          OSubM: r_q[f1*WS +: WS] <= WS'(r2 - rm);
          OLex: lex_q <= r_q[12*WS +: WS] != '0 ? r_q[13*WS-1] :
                         r_q[13*WS +: WS] != '0 ? r_q[14*WS-1] :
                         r_q[14*WS +: WS] != '0 ? r_q[15*WS-1] : 1'b1;
          OClr: t_q <= '0;
          OMul: begin
            b_q <= {{(WB-WS){r2[WS-1]}}, r2};
            p_q <= '0;
          end
          OChkAcc: res_q <= acc_q < 0 ? 2'b11 : 2'b01;
          OChkT: res_q <= t_q < 0 ? 2'b11 : 2'b01;
          OChkV: res_q <= 2'b00;
          OLdX: x_q <= WX'(acc_q) <<< K;
          OSgnLo: lo_q <= x_q == '0 ? 2'b00 : x_q < 0 ? 2'b11 : 2'b01;
          OFin: res_q <= {1'b0, in_range};
          default: res_q <= 2'b00;  // OEnd: every term zero
        endcase
      end
      SMul: begin
        p_q <= p_next;
        b_q <= b_q << DigitW;
      end
      SMulAdd: begin
        unique case (dst)
          DT: t_q <= neg ? t_q - WT'(p_q) : t_q + WT'(p_q);
          DAcc: acc_q <= neg ? acc_q - WACC'(p_q) : acc_q + WACC'(p_q);
          DV: acc2_q <= neg ? acc2_q - WACC'(p_q) : acc2_q + WACC'(p_q);
          default: x_q <= neg ? x_q - WX'(p_q) : x_q + WX'(p_q);
        endcase
      end
      default: ;
    endcase
  end
endmodule
