// ru_pipe: the pipeline / delay register block of every rayunits unit (FP units, ray units,
// noise unit): the registers ru_pipe_pkg places, the delay lines of values that skip levels,
// the output registers beyond the useful maximum.
//
// Depth = 0: a wire (valid_o = valid_i, data_o = data_i).
// Depth = n: n register stages. The valid bits are reset by rst_ni (active low, asynchronous),
// so a reset drops every result in flight; the data registers have no reset and load every
// cycle (their contents only matter while the matching valid bit is set). A delay line whose
// valid output is not needed leaves it unused (synthesis removes those flip-flops).
// One always_ff per stage (no whole-vector defaults), so wide and deep delay lines (volumes at
// e11m52 across a division level) stay cheap to elaborate.
module ru_pipe #(
  parameter int unsigned Width = 1,
  parameter int unsigned Depth = 0
) (
  input  logic             clk_i,
  input  logic             rst_ni,
  input  logic             valid_i,
  input  logic [Width-1:0] data_i,
  output logic             valid_o,
  output logic [Width-1:0] data_o
);

  if (Depth == 0) begin : gen_wire
    assign valid_o = valid_i;
    assign data_o  = data_i;
    logic unused_clk_rst;
    assign unused_clk_rst = clk_i ^ rst_ni;
  end else begin : gen_regs
    logic [Depth-1:0]       valid_q;
    logic [Depth*Width-1:0] data_q;

    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        valid_q[0] <= 1'b0;
      end else begin
        valid_q[0] <= valid_i;
      end
    end
    always_ff @(posedge clk_i) data_q[0+:Width] <= data_i;

    for (genvar i = 1; i < Depth; i++) begin : gen_stage
      always_ff @(posedge clk_i or negedge rst_ni) begin
        if (!rst_ni) begin
          valid_q[i] <= 1'b0;
        end else begin
          valid_q[i] <= valid_q[i-1];
        end
      end
      always_ff @(posedge clk_i) data_q[i*Width+:Width] <= data_q[(i-1)*Width+:Width];
    end

    assign valid_o = valid_q[Depth-1];
    assign data_o  = data_q[(Depth-1)*Width+:Width];
  end

endmodule
