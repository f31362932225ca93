// rayunits tb: main() of every Verilated test executable (see testing.hpp for the options).
#include <gtest/gtest.h>

#include <exception>
#include <iostream>

#include "rayunits/tb/testing.hpp"

int main(int argc, char** argv) {
  if (!ru::tb::parse_options(argc, argv)) return 2;
  ::testing::InitGoogleTest(&argc, argv);
  try {
    if (!ru::tb::register_all_tests()) return 2;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  if (!::testing::GTEST_FLAG(list_tests))
    std::cerr << "tb: seed=" << ru::tb::global_options().seed
            << " (reproduce with --seed=N or RU_SEED=N)\n";
  return RUN_ALL_TESTS();
}
