#pragma once
// The median of a sample (the upper of the two middle values for an even count; 0 for none),
// and any quantile of it (the value at rank floor(q n), q in [0, 1)).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace ts {

// Reorders *values.
template <class T>
double QuantileInPlace(std::vector<T>* values, double q) {
  if (values->empty()) return 0.0;
  const size_t rank = std::min(values->size() - 1, static_cast<size_t>(q * values->size()));
  const auto at = values->begin() + static_cast<std::ptrdiff_t>(rank);
  std::nth_element(values->begin(), at, values->end());
  return static_cast<double>(*at);
}

template <class T>
double MedianInPlace(std::vector<T>* values) {
  return QuantileInPlace(values, 0.5);
}

template <class T>
double Median(std::vector<T> values) {
  return MedianInPlace(&values);
}

}  // namespace ts
