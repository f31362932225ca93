// rayunits util: the commit a result was made from (run through util::run_process, no shell).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace ru::util {

struct CommitInfo {
  std::string hash;    // HEAD (full, or git's abbreviation with short_hash)
  bool dirty = false;  // tracked files (under pathspec, if given) differ from HEAD
};

// HEAD of the repository containing source_dir; nullopt without git, outside a repository or
// before the first commit.
std::optional<CommitInfo> git_commit_info(const std::string& source_dir, bool short_hash = false,
                                          const std::vector<std::string>& pathspec = {});

// Content identity of one directory of the repository: git's tree id of `path` at HEAD, followed by
// "+<FNV-1a 64 of `git diff HEAD -- path`>" when it has uncommitted changes; "" without git or
// outside a repository. Changes only when something under `path` changes (not on every commit).
std::string git_tree_id(const std::string& source_dir, const std::string& path);

// "<HEAD>", "<HEAD> (with uncommitted changes)" or "unknown" (the reports' commit line).
std::string git_commit(const std::string& source_dir);

}  // namespace ru::util
