// Atomic file writing: content goes to "<path>.tmp.<pid>" and is renamed onto <path> only when
// commit() succeeds, so a crash or an error never leaves a half-written file behind.
//
// Several outputs of one command are all-or-nothing with an OutputTransaction: while one is
// active on this thread, AtomicFile::commit() (and so every writer built on it) only finishes
// its temporary; OutputTransaction::commit() then renames every temporary onto its path, or
// none (a failed rename puts the files already renamed back as they were).
#pragma once

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace inhap {

class AtomicFile {
 public:
  /// Opens a temporary file beside `path` (binary mode). Throws IoError (inhap::Error when
  /// `path` is a directory).
  explicit AtomicFile(std::string path);
  ~AtomicFile();  ///< removes the temporary file if commit() was not called
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(std::string_view bytes);
  void write(const void* data, std::size_t size);
  std::FILE* handle() { return file_; }
  /// Flushes and closes the temporary, then renames it onto the final path (or hands it to the
  /// active OutputTransaction, which renames it at its own commit). Throws IoError.
  void commit();
  const std::string& path() const { return path_; }

 private:
  std::string path_, tmp_;
  std::FILE* file_ = nullptr;
};

/// All-or-nothing outputs: construct one before writing a command's outputs, call commit() after
/// the last. Destroyed without commit() (an exception), it removes every temporary and leaves
/// the old outputs untouched. Transactions on one thread do not nest (an inner one is an error).
class OutputTransaction {
 public:
  OutputTransaction();
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  /// Renames every finished temporary onto its path, in the order written. If a rename fails,
  /// the outputs renamed before it are restored (old content, or removed if there was none), the
  /// other temporaries removed, and IoError thrown.
  void commit();
  /// Called by AtomicFile::commit(): `tmp` is finished and waits to become `path`.
  void defer(std::string tmp, std::string path);
  /// The transaction active on this thread, or nullptr.
  static OutputTransaction* active();

 private:
  struct Pending {
    std::string tmp, path;
  };
  std::vector<Pending> pending_;
  bool done_ = false;
};

/// A folder for a command's outputs (`--out-dir`, the demo's OUT): created with its missing
/// parents, before long work. Destroyed before keep() (an error on the way), it removes the
/// folders it created again when they are empty, so a failed command leaves the file system as
/// it found it. Declare it before the OutputTransaction whose files go into it. Throws inhap::Error
/// naming the path when it is a file or cannot be created.
class OutputFolder {
 public:
  explicit OutputFolder(std::string path);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  void keep() { keep_ = true; }

 private:
  std::string path_;
  std::vector<std::string> created_;  ///< folders this created, deepest first
  bool keep_ = false;
};

/// Checks, before long work, that `path` can be written: its folder exists and takes a new
/// file, and it is not a directory. Throws inhap::Error naming the path and the reason.
void check_output_path(const std::string& path);

/// Writes a whole string atomically.
void write_file_atomic(const std::string& path, std::string_view content);
/// Reads a whole file. Throws IoError (inhap::Error for a directory).
std::string read_file(const std::string& path);

/// Fault injection for tests of all-or-nothing outputs: the n-th AtomicFile::write (counting
/// from 1, every file) or the n-th rename onto a final path then fails as an I/O error would.
/// 0 turns a fault off. Not for production use (a process-wide counter, not thread-safe).
namespace fault {
void fail_nth_write(long n);
void fail_nth_rename(long n);
/// The same across the process boundary: INHAP_TEST_FAIL_NTH_WRITE=n /
/// INHAP_TEST_FAIL_NTH_RENAME=n (unset, empty or not positive: no fault). What the program calls
/// at start.
void from_environment();
}  // namespace fault

}  // namespace inhap
