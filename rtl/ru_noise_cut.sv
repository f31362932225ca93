// ru_noise_cut: one optional pipeline register of ru_noise (a cut point of the datapath).
//
// Reg = 0: a wire. Reg = 1: one register stage; the valid bit is reset by rst_ni (active low,
// asynchronous) so a reset drops the result in flight; the data register has no reset and loads
// every cycle (its contents only matter while the valid bit is set).
module ru_noise_cut #(
  parameter int unsigned Width = 1,
  parameter bit          Reg   = 1'b0
) (
  input  logic             clk_i,
  input  logic             rst_ni,
  input  logic             valid_i,
  input  logic [Width-1:0] data_i,
  output logic             valid_o,
  output logic [Width-1:0] data_o
);

  if (Reg) begin : gen_reg
    logic             valid_q;
    logic [Width-1:0] data_q;

    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        valid_q <= 1'b0;
      end else begin
        valid_q <= valid_i;
      end
    end

    always_ff @(posedge clk_i) begin
      data_q <= data_i;
    end

    assign valid_o = valid_q;
    assign data_o  = data_q;
  end else begin : gen_wire
    assign valid_o = valid_i;
    assign data_o  = data_i;
    logic unused_clk_rst;
    assign unused_clk_rst = clk_i ^ rst_ni;
  end

endmodule
