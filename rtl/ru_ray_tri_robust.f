// ru_ray_tri_robust (Kensler Fig. 3.6) and the FP units it is built from
ru_fp_pkg.sv
ru_ray_tri_pkg.sv
ru_fp_pipe.sv
ru_lzc.sv
ru_fp_classify.sv
ru_fp_normalize.sv
ru_fp_round_pack.sv
ru_umul.sv
ru_fp_add.sv
ru_fp_mul.sv
ru_fp_div.sv
ru_fp_cmp.sv
ru_ray_tri_delay.sv
ru_ray_tri_vsub.sv
ru_ray_tri_cross.sv
ru_fp_dot3_core.sv
ru_ray_tri_robust.sv
