ru_pipe_pkg.sv
ru_fp_pkg.sv
ru_pipe.sv
ru_fp_classify.sv
ru_fp_cmp.sv
