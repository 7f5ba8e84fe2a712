#include "evaluation/sweep/unit_kinds.h"

#include <mutex>

namespace mavloc {
namespace {

std::mutex& SweepUnitKindsMutex() {
  static std::mutex mutex;
  return mutex;
}

std::map<std::string, SweepUnitKind>& RegisteredSweepUnitKinds() {
  static std::map<std::string, SweepUnitKind> kinds;
  return kinds;
}

}  // namespace

void RegisterSweepUnitKind(const std::string& name, SweepUnitKind run) {
  const std::lock_guard<std::mutex> lock(SweepUnitKindsMutex());
  RegisteredSweepUnitKinds()[name] = std::move(run);
}

const SweepUnitKind* FindSweepUnitKind(const std::string& name) {
  const std::lock_guard<std::mutex> lock(SweepUnitKindsMutex());
  const auto it = RegisteredSweepUnitKinds().find(name);
  return it == RegisteredSweepUnitKinds().end() ? nullptr : &it->second;
}

}  // namespace mavloc
