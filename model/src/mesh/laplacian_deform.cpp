#include "leafdig/model/mesh/laplacian_deform.hpp"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <map>
#include <string>

#include "leafdig/model/errors.hpp"

namespace leafdig::model {

std::vector<Eigen::Vector3d> laplacianDeform(const Mesh& mesh,
                                             const std::vector<std::pair<std::uint32_t, Eigen::Vector3d>>& handles) {
  const auto n = static_cast<Eigen::Index>(mesh.positions.size());
  // Cotangent weights: edge (i, j) gets cot of the angle opposite it in each of its triangles.
  std::vector<std::map<std::uint32_t, double>> w(mesh.positions.size());
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = t[static_cast<std::size_t>((k + 1) % 3)];
      const std::uint32_t j = t[static_cast<std::size_t>((k + 2) % 3)];
      const Eigen::Vector3d e1 = mesh.positions[i] - mesh.positions[t[static_cast<std::size_t>(k)]];
      const Eigen::Vector3d e2 = mesh.positions[j] - mesh.positions[t[static_cast<std::size_t>(k)]];
      const double cross = e1.cross(e2).norm();
      const double cot = cross > 0.0 ? e1.dot(e2) / cross : 0.0;
      w[i][j] += cot;
      w[j][i] += cot;
    }
  }
  // Every connected part of the mesh needs a handle, or it floats (L has constant vectors in
  // its kernel, one per part).
  std::vector<std::uint32_t> part(mesh.positions.size());
  for (std::uint32_t i = 0; i < part.size(); ++i) part[i] = i;
  const auto find = [&](std::uint32_t i) {
    while (part[i] != i) i = part[i] = part[part[i]];
    return i;
  };
  for (const auto& t : mesh.triangles) {
    part[find(t[1])] = find(t[0]);
    part[find(t[2])] = find(t[0]);
  }
  std::vector<char> held(mesh.positions.size(), 0);
  for (const auto& h : handles) {
    if (h.first < held.size()) held[find(h.first)] = 1;
  }
  for (std::uint32_t i = 0; i < part.size(); ++i) {
    if (!held[find(i)]) {
      throw InputError("laplacianDeform: vertex " + std::to_string(i) +
                       " is in a part of the mesh with no handle; hold at least one vertex of every part");
    }
  }
  std::vector<char> fixed(mesh.positions.size(), 0);
  Eigen::MatrixXd target = Eigen::MatrixXd::Zero(n, 3);
  for (const auto& [index, p] : handles) {
    if (index >= mesh.positions.size()) throw InputError("laplacianDeform: handle index out of range");
    fixed[index] = 1;
    target.row(index) = p.transpose();
  }
  // L: row i = v_i - sum_j d_ij v_j with d_ij = w_ij / sum_j w_ij (sum 1, seed 001); a row
  // whose cotangents cancel (obtuse fans) falls back to uniform weights.
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& row = w[static_cast<std::size_t>(i)];
    if (row.empty()) {
      if (!fixed[static_cast<std::size_t>(i)]) {
        throw InputError("laplacianDeform: vertex " + std::to_string(i) + " is free but in no triangle");
      }
      continue;
    }
    double sum = 0.0;
    double sumAbs = 0.0;
    for (const auto& [j, wij] : row) {
      sum += wij;
      sumAbs += std::abs(wij);
    }
    const bool uniform = std::abs(sum) <= 1e-9 * sumAbs || sumAbs == 0.0;
    entries.emplace_back(i, i, 1.0);
    for (const auto& [j, wij] : row) {
      entries.emplace_back(i, static_cast<Eigen::Index>(j),
                           uniform ? -1.0 / static_cast<double>(row.size()) : -wij / sum);
    }
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(entries.begin(), entries.end());
  Eigen::MatrixXd V(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) V.row(i) = mesh.positions[static_cast<std::size_t>(i)].transpose();
  const Eigen::MatrixXd delta = L * V;

  // Unknowns: the free vertices. Minimise |L_F x_F - (delta - L_H x_H)|^2.
  std::vector<Eigen::Index> freeIndex(mesh.positions.size(), -1);
  Eigen::Index freeCount = 0;
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    if (!fixed[i]) freeIndex[i] = freeCount++;
  }
  std::vector<Eigen::Vector3d> out(mesh.positions);
  for (const auto& [index, p] : handles) out[index] = p;
  if (freeCount == 0) return out;
  std::vector<Eigen::Triplet<double>> freeEntries;
  Eigen::MatrixXd rhs = delta;
  for (int k = 0; k < L.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, k); it; ++it) {
      const auto col = static_cast<std::size_t>(it.col());
      if (freeIndex[col] >= 0) {
        freeEntries.emplace_back(it.row(), freeIndex[col], it.value());
      } else {
        rhs.row(it.row()) -= it.value() * target.row(it.col());
      }
    }
  }
  Eigen::SparseMatrix<double> LF(n, freeCount);
  LF.setFromTriplets(freeEntries.begin(), freeEntries.end());
  const Eigen::SparseMatrix<double> normal = LF.transpose() * LF;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  if (solver.info() != Eigen::Success) {
    throw InputError(
        "laplacianDeform: the handles leave part of the mesh free to float; hold at least one vertex of every part");
  }
  const Eigen::MatrixXd x = solver.solve(LF.transpose() * rhs);
  if (solver.info() != Eigen::Success || !x.allFinite()) {
    throw InputError("laplacianDeform: the deformation has no unique solution; hold more of the mesh");
  }
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    if (freeIndex[i] >= 0) out[i] = x.row(freeIndex[i]).transpose();
  }
  return out;
}

}  // namespace leafdig::model
