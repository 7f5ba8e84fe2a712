// Kalibr's aprilgrid tag family for libapriltag: the 587 codes of tag36h11 with a 2-bit black
// border (kalibr/aslam_cv's GridCalibrationTargetAprilgrid draws its tags with the AprilTags C++
// library of M. Kaess, TagFamily(tag36h11, blackBorder = 2)). The stock libapriltag tag36h11 family
// has a 1-bit border and finds none of these tags.
//
// The family is built at run time from the stock tag36h11 family (libapriltag 3.3.0's
// apriltag_family_t): the same codes and bit order, every bit position shifted by one cell right
// and down (bit_x + 1, bit_y + 1: data starts after two black cells instead of one), the black
// square widened from 8 to 10 cells (width_at_border) and the whole bitmap, with its one-cell white
// ring, from 10 to 12 cells (total_width). libapriltag's decoder samples the white model one
// half-cell outside the black square and the black model one half-cell inside it, so it needs no
// other change; its quad corners are the black square's outer corners, which are exactly the
// aprilgrid's corners (Kalibr: tagSize = edge of the black square).
//
// Names: "aprilgrid" and its alias "tag36h11b2" (tag36h11, border 2).
#pragma once

#include <apriltag/apriltag.h>

#include <string>

namespace mavloc {

inline constexpr const char* kAprilgridFamilyName = "aprilgrid";
inline constexpr const char* kAprilgridFamilyAlias = "tag36h11b2";

// True for "aprilgrid" and "tag36h11b2".
bool IsAprilgridFamily(const std::string& name);

// A new family (owned by the caller, free with AprilgridFamilyDestroy after every detector using it
// has been destroyed). Never null.
apriltag_family_t* AprilgridFamilyCreate();
void AprilgridFamilyDestroy(apriltag_family_t* family);

}  // namespace mavloc
