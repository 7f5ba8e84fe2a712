// Helpers shared by the libFuzzer targets of fuzz/ (LLVM libFuzzer, "LLVMFuzzerTestOneInput"
// entry point: https://llvm.org/docs/LibFuzzer.html). The readers take paths, so each input is
// written to a file in a scratch folder of this process and read back; bad input must end in
// InputError (core/errors.h), anything else escaping a reader is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "core/errors.h"

namespace mavloc::fuzz {

// A folder of this process (under $TMPDIR or /tmp, named after the pid), created on first use and
// removed at normal exit.
const std::string& ScratchFolder();

// Writes `text` to ScratchFolder()/relative_path (parent folders created); returns the full path.
std::string WriteScratchFile(const std::string& relative_path, const std::string& text);
std::string WriteScratchFile(const std::string& relative_path, const uint8_t* data, size_t size);

// Prints the exception's message as a finding and aborts, so that libFuzzer records the input.
[[noreturn]] void ReportUnexpectedException(const char* what);

// Runs read(): InputError is the expected outcome of bad input; any other exception is a finding.
template <class Read>
void ExpectInputErrorOnly(Read&& read) {
  try {
    read();
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    ReportUnexpectedException(e.what());
  } catch (...) {
    ReportUnexpectedException("an exception not derived from std::exception");
  }
}

}  // namespace mavloc::fuzz
