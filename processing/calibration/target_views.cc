#include "processing/calibration/target_views.h"

#include <cmath>
#include <set>

namespace ts {

void TargetViews::AddFullView(const std::string& name, int placement,
                              const std::vector<Eigen::Vector2d>& pixels) {
  TargetView view{name, placement, {}, pixels};
  for (size_t i = 0; i < pixels.size(); ++i) view.ids.push_back(static_cast<int>(i));
  views.push_back(std::move(view));
}

int TargetViews::Observations() const {
  int n = 0;
  for (const TargetView& v : views) n += static_cast<int>(v.pixels.size());
  return n;
}

FrameCoverage TargetViews::Coverage() const {
  constexpr int kColumns = FrameCoverage::kColumns, kRows = FrameCoverage::kRows;
  FrameCoverage f;
  f.counts.assign(kColumns * kRows, 0);
  for (const TargetView& v : views)
    for (const Eigen::Vector2d& p : v.pixels) {
      const int i = static_cast<int>(std::floor(p.x() / width_px * kColumns));
      const int j = static_cast<int>(std::floor(p.y() / height_px * kRows));
      if (i >= 0 && i < kColumns && j >= 0 && j < kRows) ++f.counts[j * kColumns + i];
    }
  int covered = 0, border = 0, border_covered = 0;
  for (int j = 0; j < kRows; ++j)
    for (int i = 0; i < kColumns; ++i) {
      const bool seen = f.counts[j * kColumns + i] > 0;
      const bool edge = i == 0 || j == 0 || i == kColumns - 1 || j == kRows - 1;
      covered += seen;
      border += edge;
      border_covered += edge && seen;
    }
  f.share = static_cast<double>(covered) / (kColumns * kRows);
  f.border_share = static_cast<double>(border_covered) / border;
  return f;
}

bool TargetViews::Planar() const {
  for (const Eigen::Vector3d& p : target)
    if (p.z() != 0.0) return false;
  return true;
}

Status TargetViews::Check() const {
  if (width_px <= 0 || height_px <= 0) return Error{"the image size is not known"};
  for (const Eigen::Vector3d& p : target)
    if (!p.allFinite()) return Error{"a target point is not finite"};
  if (!target_sigma.empty() && target_sigma.size() != target.size())
    return Error{"one sigma per target point is needed"};
  for (double sigma : target_sigma)
    if (!(sigma >= 0.0 && std::isfinite(sigma)))
      return Error{"a target point's sigma is not a finite, non-negative number"};
  for (const TargetView& v : views) {
    if (v.ids.size() != v.pixels.size())
      return Error{"view " + v.name + ": one target id per pixel is needed"};
    std::set<int> seen;
    for (size_t i = 0; i < v.ids.size(); ++i) {
      if (v.ids[i] < 0 || v.ids[i] >= static_cast<int>(target.size()))
        return Error{"view " + v.name + ": target id " + std::to_string(v.ids[i]) +
                     " is not in the target"};
      if (!seen.insert(v.ids[i]).second)
        return Error{"view " + v.name + ": target id " + std::to_string(v.ids[i]) + " twice"};
      if (!v.pixels[i].allFinite()) return Error{"view " + v.name + ": a pixel is not finite"};
    }
  }
  return {};
}

}  // namespace ts
