#pragma once
// A fill-reducing ordering of a symmetric sparsity pattern for sparse Cholesky, by CHOLMOD's AMD
// and, from `both_from` columns, METIS too: the one whose factorization takes fewer
// floating-point operations is kept (AMD on a tie). CHOLMOD's own choice among several methods is
// the factor with fewer nonzeros, which can take more operations to compute.
// Invariant: the ordering is postordered (each elimination subtree contiguous), and it is a
// function of the pattern alone.

#include <cholmod.h>

#include <cstddef>
#include <optional>
#include <vector>

namespace hydra_multi {

enum class OrderingMethod { kAmd, kMetis };

struct FillReducingOrdering {
  OrderingMethod method = OrderingMethod::kAmd;
  std::vector<long> column;  ///< per place in the ordering, the column placed there
  double flops = 0.0;        ///< of one factorization in this order (CHOLMOD's count)
  double nonzeros = 0.0;     ///< of the factor in this order
};

/// A square CHOLMOD pattern matrix with, per column, the rows `rows` lists (sorted), stored as
/// the triangle `stype` says (1 upper, -1 lower); null where CHOLMOD cannot allocate it.
cholmod_sparse* patternMatrix(const std::vector<std::vector<long>>& rows, int stype,
                              cholmod_common& common);

/// `rows`: per column c, the rows r <= c of its entries (c itself included), sorted. `only`: that
/// method alone. Empty if no method succeeded (out of memory).
std::optional<FillReducingOrdering> orderForCholesky(const std::vector<std::vector<long>>& rows,
                                                     size_t both_from,
                                                     std::optional<OrderingMethod> only = {});

}  // namespace hydra_multi
