ru_pipe_pkg.sv
ru_pipe.sv
ru_branch.sv
