#pragma once
// A pose of the rig's 2-axis stage (DESIGN.md "Frames"): pan clockwise seen from above, tilt
// positive upward, both in degrees.
namespace ts {

struct StagePose {
  double pan_deg = 0.0;
  double tilt_deg = 0.0;
};

}  // namespace ts
