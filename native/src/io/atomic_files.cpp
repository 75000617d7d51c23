#include <shadecut/io/atomic_files.hpp>

#include <shadecut/support/errors.hpp>

#include <atomic>
#include <filesystem>
#include <system_error>

#include <unistd.h>

namespace shadecut {

namespace fs = std::filesystem;

namespace {

// Two threads of one process may stage the same name at once: the counter keeps their files apart.
std::atomic<unsigned> staged_count{0};

}  // namespace

StagedFiles::~StagedFiles() {
  std::error_code ignored;
  for (const Entry& entry : entries_) fs::remove(entry.temporary, ignored);
}

std::string StagedFiles::stage(const std::string& path) {
  const fs::path final_path(path);
  std::error_code status;
  // A rename cannot replace a folder; refusing now keeps the other files of the set unchanged.
  if (fs::is_directory(final_path, status)) throw IoError("cannot write \"" + path + "\": it is a folder");
  const std::string name = "." + final_path.stem().string() + "." + std::to_string(::getpid()) + "-" +
                           std::to_string(staged_count.fetch_add(1)) + ".partial" + final_path.extension().string();
  const std::string temporary = (final_path.parent_path() / name).string();
  entries_.push_back({temporary, path});
  return temporary;
}

void StagedFiles::commit() {
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    std::error_code error;
    fs::rename(entries_[i].temporary, entries_[i].final, error);
    if (error) {
      std::string missing;
      for (std::size_t k = i; k < entries_.size(); ++k) missing += (k > i ? ", " : "") + entries_[k].final;
      throw IoError("cannot write " + missing + ": " + error.message());
    }
    entries_[i].temporary.clear();
  }
  entries_.clear();
}

void write_atomically(const std::string& path, const std::function<void(const std::string& temporary)>& writer) {
  StagedFiles staged;
  writer(staged.stage(path));
  staged.commit();
}

}  // namespace shadecut
