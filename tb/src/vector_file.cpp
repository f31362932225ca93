// rayunits tb: vector files (see vector_file.hpp and tb/README.md).
#include "rayunits/tb/vector_file.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace ru::tb {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> t;
  std::istringstream is(line);
  std::string w;
  while (is >> w) t.push_back(w);
  return t;
}

std::string strip_comment(const std::string& l) {
  const size_t h = l.find('#');
  return h == std::string::npos ? l : l.substr(0, h);
}

template <class F>
VectorFile read(const std::string& path, F&& on_vector) {
  std::ifstream is(path);
  if (!is) throw std::runtime_error(path + ": cannot open the vector file");
  VectorFile vf;
  vf.path = path;
  std::string line;
  int n = 0;
  bool seen_vector = false;
  while (std::getline(is, line)) {
    ++n;
    const auto tok = split(strip_comment(line));
    if (tok.empty()) continue;
    auto where = [&] { return path + ":" + std::to_string(n) + ": "; };
    if (tok[0] == "format" || tok[0] == "round") {
      if (tok.size() != 2) throw std::runtime_error(where() + "'" + tok[0] + "' takes one value");
      if (seen_vector) throw std::runtime_error(where() + "'" + tok[0] + "' must come before the vectors");
      (tok[0] == "format" ? vf.format : vf.round) = tok[1];
      continue;
    }
    seen_vector = true;
    try {
      on_vector(vf, n, tok);
    } catch (const std::exception& e) {
      throw std::runtime_error(where() + e.what());
    }
  }
  return vf;
}

}  // namespace

VectorFile read_vector_file_header(const std::string& path) {
  return read(path, [](VectorFile&, int, const std::vector<std::string>&) {});
}

VectorFile read_vector_file(const std::string& path, const UnitAdapter& adapter) {
  return read(path, [&](VectorFile& vf, int line, const std::vector<std::string>& tok) {
    FileVector v;
    v.line = line;
    size_t arrow = 0;
    while (arrow < tok.size() && tok[arrow] != "->") ++arrow;
    adapter.parse_inputs(std::vector<std::string>(tok.begin(), tok.begin() + arrow), v.in);
    if (arrow < tok.size()) {
      const std::vector<std::string> outs(tok.begin() + arrow + 1, tok.end());
      adapter.parse_outputs(outs, v.out, v.out_mask);
    }
    vf.vectors.push_back(v);
  });
}

}  // namespace ru::tb
