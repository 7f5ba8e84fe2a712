#include "frontends/apriltag/aprilgrid_family.h"

#include <apriltag/tag36h11.h>

#include <algorithm>
#include <cstring>

namespace mavloc {

namespace {

// One extra black cell on each side of tag36h11's 1-cell border.
constexpr int kExtraBorderCells = 1;

}  // namespace

bool IsAprilgridFamily(const std::string& name) {
  return name == kAprilgridFamilyName || name == kAprilgridFamilyAlias;
}

apriltag_family_t* AprilgridFamilyCreate() {
  apriltag_family_t* stock = tag36h11_create();
  auto* family = new apriltag_family_t{};
  family->ncodes = stock->ncodes;
  family->codes = new uint64_t[stock->ncodes];
  std::copy(stock->codes, stock->codes + stock->ncodes, family->codes);
  family->nbits = stock->nbits;
  family->bit_x = new uint32_t[stock->nbits];
  family->bit_y = new uint32_t[stock->nbits];
  for (uint32_t i = 0; i < stock->nbits; ++i) {
    family->bit_x[i] = stock->bit_x[i] + kExtraBorderCells;
    family->bit_y[i] = stock->bit_y[i] + kExtraBorderCells;
  }
  family->width_at_border = stock->width_at_border + 2 * kExtraBorderCells;
  family->total_width = stock->total_width + 2 * kExtraBorderCells;
  family->reversed_border = stock->reversed_border;
  family->h = stock->h;
  const size_t name_length = std::strlen(kAprilgridFamilyName);
  family->name = new char[name_length + 1];
  std::memcpy(family->name, kAprilgridFamilyName, name_length + 1);
  family->impl = nullptr;  // filled (and freed) by the detector that adds the family
  tag36h11_destroy(stock);
  return family;
}

void AprilgridFamilyDestroy(apriltag_family_t* family) {
  if (family == nullptr) return;
  delete[] family->codes;
  delete[] family->bit_x;
  delete[] family->bit_y;
  delete[] family->name;
  delete family;
}

}  // namespace mavloc
