#pragma once
// A duration as reports and timelines state it: seconds, as a double.
#include <chrono>

namespace ts {

template <class Rep, class Period>
double Seconds(std::chrono::duration<Rep, Period> d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace ts
