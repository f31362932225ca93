// rayunits tb: vector files (format in tb/README.md, "Vector files").
//
//   # comment                       blank lines and '#' comments are ignored
//   format e8m23                    optional: the file is for this format (eXmY[-ftz])
//   round rtz                       optional: ... and this rounding mode (rne default)
//   mul 0x3fc00000 2.5              one vector: op name, operands (hex bit pattern or decimal)
//   add 1 2 -> 0x40400000 -         optional "->" and expected outputs (unit-specific; "?"
//                                   leaves a field unchecked); checked against the golden model
//
// The adapter parses operands and outputs (UnitAdapter::parse_inputs / parse_outputs).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rayunits/tb/harness.hpp"

namespace ru::tb {

struct FileVector {
  int line = 0;
  Record in{};
  Record out{};
  uint32_t out_mask = 0;  // output fields given in the file
};

struct VectorFile {
  std::string path;
  std::string format;  // "" when the file has no format line
  std::string round;   // "" when the file has no round line
  std::vector<FileVector> vectors;
};

// Reads only the header (format/round lines) of a vector file. Throws std::runtime_error.
VectorFile read_vector_file_header(const std::string& path);
// Reads and parses the whole file with the adapter. Throws std::runtime_error("path:line: ...").
VectorFile read_vector_file(const std::string& path, const UnitAdapter& adapter);

}  // namespace ru::tb
