#include "assembly/material.hpp"

#include <cstddef>

namespace nd {

CellMaterials cell_materials(const Material &fallback, const std::map<int, Material> &by_region,
                             const std::vector<int> &cell_region) {
  CellMaterials m(fallback);
  if (by_region.empty() || cell_region.empty()) return m;
  std::map<int, int> slot;  // region -> index into the list (equal materials share one)
  for (const auto &[region, mat] : by_region) {
    int k = 0;
    while (k < static_cast<int>(m.list.size()) && !(m.list[k] == mat)) ++k;
    if (k == static_cast<int>(m.list.size())) m.list.push_back(mat);
    slot[region] = k;
  }
  if (m.list.size() == 1) return m;  // every region's material is the default's: one material
  m.index.assign(cell_region.size(), 0);
  for (std::size_t c = 0; c < cell_region.size(); ++c)
    if (auto it = slot.find(cell_region[c]); it != slot.end()) m.index[c] = it->second;
  return m;
}

}  // namespace nd
