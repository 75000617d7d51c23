// Files that appear whole or not at all: written under a temporary name beside their final name and
// renamed onto it only when complete (a rename within one folder replaces the old file in one step).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace shadecut {

/// Files staged under temporary names and moved onto their names together by commit(). Until then the
/// files at those names stay as they were; destroying the set without commit() (a failure, an
/// interruption) removes every temporary file it handed out.
class StagedFiles {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();

  /// The temporary name to write `path` to: ".<name>.<process>-<n>.partial<extension>" in its folder,
  /// so that the rename stays within one file system and writers that choose the format by the
  /// extension (OpenImageIO) still find it. Throws IoError when `path` is a folder.
  std::string stage(const std::string& path);

  /// Renames every staged file onto its name. Throws IoError naming the files not moved.
  void commit();

 private:
  struct Entry {
    std::string temporary, final;
  };
  std::vector<Entry> entries_;
};

/// Calls `writer` with a temporary name for `path` and renames the result onto `path` when the writer
/// returns: a writer that throws (a full disk, a file size limit) leaves an existing file untouched
/// and no temporary file behind.
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& writer);

}  // namespace shadecut
