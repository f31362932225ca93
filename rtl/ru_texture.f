ru_pipe_pkg.sv
ru_pipe.sv
ru_noise.sv
ru_noise_trunc.sv
ru_texture.sv
