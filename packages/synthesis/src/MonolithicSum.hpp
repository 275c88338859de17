// Internal to the synthesis package: the sum of c T^T A T over the
// substructures whose u = T q is sparse (Full bases: the truth model), formed
// the way a finite element code assembles a monolithic model with its
// attachments eliminated (doc/theory.md §11.2, "The truth, assembled
// monolithically"; issue 18).
//
// A Full basis makes T nearly the identity: each free row is one coordinate;
// a held row of a RigidFit attachment is a combination of the parent's face
// coordinates, and in the relative (floating frame) form each row also
// carries the six rigid coordinates of its attachment. So T^T A T is formed
// row by row of A: W_i = sum_j a_ij T_j (a sparse accumulator over the
// coordinates), then (T^T W)_p = sum_i t_ip W_i gathered per coordinate p
// into the upper triangle. The entries of every add are bucketed by row at
// the end, and the lower triangle written as the mirror of the upper (times
// -1 for a skew G), so the sum is symmetric (skew) exactly on one rank. No sparse
// matrix-matrix product, transpose or sum of Tpetra matrices is formed:
// those took 40 s of the 1.3e5-DOF rotor's truth (doc/benchmarks.md).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include <Teuchos_Comm.hpp>

#include "cms/core/TpetraTypes.hpp"

namespace cms::synthesis::detail {

class MonolithicSum {
public:
  /// `sign` +1: A symmetric (M, K, D); -1: A skew (G), whose diagonal is 0.
  explicit MonolithicSum(double sign = 1.0) : sign_(sign) {}

  using Row = std::vector<std::pair<GlobalOrdinal, double>>;
  /// Adds c T^T A T. T: u = T q (rows: A's row map, columns: the structure's
  /// n coordinates, global ids, then the virtual ones n + v: a
  /// substructure's attachment motion, v = 0 .. motion.size() - 1, whose
  /// value over q is motion[v]); A square on T's row map, fill-complete.
  /// The product is formed with the virtual coordinates, then expanded
  /// through `motion` (a RigidFit's face block as H^T B H, B 6 x 6).
  /// Collective (T's rows for A's off-rank columns are imported).
  void add(const CrsMatrix& T, const CrsMatrix& A, double c, GlobalOrdinal n, const std::vector<Row>& motion);
  /// Whether add was ever called on any rank (collective).
  bool empty(const Teuchos::Comm<int>& comm) const;
  /// The sum on `map` (the coordinates' map; domain and range too).
  /// Collective; releases the entries.
  Teuchos::RCP<const CrsMatrix> matrix(const Teuchos::RCP<const Map>& map);

private:
  struct Entry {
    GlobalOrdinal row, col;
    double value;
  };
  /// The entries added since `start` with a virtual column, expanded (add).
  void expandMotion(std::size_t start, GlobalOrdinal n, const std::vector<Row>& motion);
  double sign_;
  std::vector<Entry> entries_;  ///< upper triangle (row <= col); each add's sorted, rows may repeat across adds
  bool added_ = false;
};

}  // namespace cms::synthesis::detail
