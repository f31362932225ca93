ru_pipe_pkg.sv
ru_pipe.sv
ru_int_alu.sv
