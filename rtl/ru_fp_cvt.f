ru_pipe_pkg.sv
ru_fp_pkg.sv
ru_pipe.sv
ru_lzc.sv
ru_fp_classify.sv
ru_fp_normalize.sv
ru_fp_round_pack.sv
ru_fp_cvt.sv
