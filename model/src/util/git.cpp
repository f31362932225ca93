// rayunits util: commit lookup (see rayunits/util/git.hpp).
#include "rayunits/util/git.hpp"

#include "rayunits/util/hash.hpp"
#include "rayunits/util/process.hpp"

namespace ru::util {

std::optional<CommitInfo> git_commit_info(const std::string& source_dir, bool short_hash,
                                          const std::vector<std::string>& pathspec) {
  const std::string git = find_program("git");
  if (git.empty()) return std::nullopt;
  ProcessOptions o;
  o.out = Redirect::capture();
  o.err = Redirect::null();
  o.timeout_s = 10;
  try {
    std::vector<std::string> rev = {git, "-C", source_dir, "rev-parse"};
    if (short_hash) rev.push_back("--short");
    rev.push_back("HEAD");
    ProcessResult r = run_process(rev, o);
    std::string head = r.out;
    while (!head.empty() && (head.back() == '\n' || head.back() == '\r' || head.back() == ' ')) head.pop_back();
    if (r.exit_code != 0 || head.size() < 4 || head.find_first_not_of("0123456789abcdef") != std::string::npos)
      return std::nullopt;
    std::vector<std::string> st = {git, "-C", source_dir, "status", "--porcelain", "--untracked-files=no"};
    if (!pathspec.empty()) {
      st.push_back("--");
      st.insert(st.end(), pathspec.begin(), pathspec.end());
    }
    ProcessResult d = run_process(st, o);
    return CommitInfo{head, d.exit_code != 0 || !d.out.empty()};
  } catch (const ProcessError&) {
    return std::nullopt;
  }
}

std::string git_tree_id(const std::string& source_dir, const std::string& path) {
  const std::string git = find_program("git");
  if (git.empty()) return "";
  ProcessOptions o;
  o.out = Redirect::capture();
  o.err = Redirect::null();
  o.timeout_s = 30;
  try {
    ProcessResult r = run_process({git, "-C", source_dir, "rev-parse", "HEAD:" + path}, o);
    std::string tree = r.out;
    while (!tree.empty() && (tree.back() == '\n' || tree.back() == ' ')) tree.pop_back();
    if (r.exit_code != 0 || tree.empty() || tree.find_first_not_of("0123456789abcdef") != std::string::npos) return "";
    ProcessResult d = run_process({git, "-C", source_dir, "diff", "--no-ext-diff", "HEAD", "--", path}, o);
    if (d.exit_code != 0) return tree + "+unknown";
    if (d.out.empty()) return tree;
    return tree + "+" + fnv1a64_hex(d.out);
  } catch (const ProcessError&) {
    return "";
  }
}

std::string git_commit(const std::string& source_dir) {
  const auto c = git_commit_info(source_dir);
  if (!c || c->hash.size() < 7) return "unknown";
  return c->dirty ? c->hash + " (with uncommitted changes)" : c->hash;
}

}  // namespace ru::util
