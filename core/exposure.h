#pragma once
// The exposure a camera starts from when nothing better is known (µs): ground in daylight at
// f/8 and gain 0 sits mid-range; the capture's exposure control corrects it from the first
// pair on. One constant for the devices, the capture, the simulator and their flags.
namespace ts {

inline constexpr double kDefaultExposureUs = 8000.0;

}  // namespace ts
