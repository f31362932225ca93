// ru_noise (Kensler gradient noise unit); ru_noise.sv includes ru_noise_tables.svh (generated)
ru_noise_cut.sv
ru_noise.sv
