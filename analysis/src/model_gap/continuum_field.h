// The axisymmetric continuum field of the initial-velocity surrogate
// (initial_velocity.h), shared by the ideal descent and the rig's transient in
// continuum_descent.cc.
#ifndef BURRLAB_ANALYSIS_SRC_MODEL_GAP_CONTINUUM_FIELD_H_
#define BURRLAB_ANALYSIS_SRC_MODEL_GAP_CONTINUUM_FIELD_H_

#include <utility>
#include <vector>

#include "burrlab/analysis/model_gap/initial_velocity.h"

namespace burrlab::analysis::continuum {

// Units of R; depth z > 0 into the sample, whose surface is z = 0. A column
// at distance s from the axis crosses the sphere (centre depth c) over
// [c - w, c + w], w = sqrt(1 - s^2); 2 pi s ds = 2 pi w dw, so the columns
// are Gauss nodes in w with weights 2 pi w dw. Each column holds the erosion
// integral phi (rho / rho0 = exp(-phi)) at depths k dz, linear between.
class Field {
 public:
  // Columns that can reach material above `deepest`, depth step
  // min(grid.depth_step, depth_ratio / 60).
  Field(const ContinuumGrid& grid, double depth_ratio, double deepest);

  // m0 / R^3 with the sphere's centre at depth c, and d m0 / dc (exact
  // trapezoid over the nodes).
  double Moment(double c, double* derivative) const;
  // m0 / R^3 at c from the running integrals of the last Refresh (linear
  // between nodes): a sum over columns, for a tick-by-tick loop.
  double FastMoment(double c) const;
  // Recomputes the running integrals after erosion.
  void Refresh();

  // Erodes for dtau with the centre at depth c (f = 1 - (r/R)^2, eq. 7.12).
  void Erode(double c, double dtau);

  double dz() const { return dz_; }

 private:
  double NodeRho(std::size_t i, int k) const { return rho_[i * nodes_ + k]; }
  double Rho(std::size_t i, double z) const;
  // int_0^z rho of column i from the running integrals.
  double Integral(std::size_t i, double z) const;

  double dz_;
  int nodes_ = 0;
  // Per node (column-major): the density rho / rho0 = exp(-phi), phi the
  // erosion integral, kept up to date by Erode so Refresh needs no exp.
  std::vector<double> w_, weight_, rho_, cumulative_;
  // Per column, the nodes eroded since the last Refresh (first > second when
  // none).
  std::vector<std::pair<int, int>> dirty_;
  // Per column, the node below which all material is fresh (the deepest node
  // ever eroded, plus one): the running integral is exact up to it and grows
  // by dz per node below it.
  std::vector<int> tail_;
};

}  // namespace burrlab::analysis::continuum

#endif  // BURRLAB_ANALYSIS_SRC_MODEL_GAP_CONTINUUM_FIELD_H_
