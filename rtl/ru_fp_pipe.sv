// ru_fp_pipe: the pipeline-register block of every rayunits unit.
//
// Depth = 0: a wire (valid_o = valid_i, data_o = data_i).
// Depth = n: n register stages. The valid bits are reset by rst_ni (active low,
// asynchronous), so a reset drops every result in flight; the data registers have no reset
// and load every cycle (their contents only matter while the matching valid bit is set).
module ru_fp_pipe #(
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
    logic [Depth-1:0]       valid_d, valid_q;
    logic [Depth*Width-1:0] data_d, data_q;

    always_comb begin
      valid_d = '0;
      data_d = '0;
      valid_d[0] = valid_i;
      data_d[Width-1:0] = data_i;
      for (int unsigned i = 1; i < Depth; i++) begin
        valid_d[i] = valid_q[i-1];
        data_d[i*Width+:Width] = data_q[(i-1)*Width+:Width];
      end
    end

    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        valid_q <= '0;
      end else begin
        valid_q <= valid_d;
      end
    end

    always_ff @(posedge clk_i) begin
      data_q <= data_d;
    end

    assign valid_o = valid_q[Depth-1];
    assign data_o  = data_q[(Depth-1)*Width+:Width];
  end

endmodule
