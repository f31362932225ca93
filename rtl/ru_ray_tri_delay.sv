// ru_ray_tri_delay: data delay line of the ray-triangle units (values that skip pipeline
// levels wait here). Depth = 0: a wire; Depth = n: n registers without reset (they load every
// cycle; the units' valid bits travel with the FP instances, which are reset).
// Unlike ru_fp_pipe it carries no valid bit and has one always_ff per stage (no whole-vector
// '0 defaults), so wide and deep delay lines (volumes at e11m52 across a division level) stay
// cheap to elaborate and lint clean.
module ru_ray_tri_delay #(
  parameter int unsigned Width = 1,
  parameter int unsigned Depth = 0
) (
  input  logic             clk_i,
  input  logic [Width-1:0] data_i,
  output logic [Width-1:0] data_o
);

  if (Depth == 0) begin : gen_wire
    assign data_o = data_i;
    logic unused_clk;
    assign unused_clk = clk_i;
  end else begin : gen_regs
    logic [Depth*Width-1:0] q;
    always_ff @(posedge clk_i) q[0+:Width] <= data_i;
    for (genvar i = 1; i < Depth; i++) begin : gen_stage
      always_ff @(posedge clk_i) q[i*Width+:Width] <= q[(i-1)*Width+:Width];
    end
    assign data_o = q[(Depth-1)*Width+:Width];
  end

endmodule
