#include "hydra_multi/optim/fill_reducing_ordering.h"

#include <cholmod.h>

#include <future>
#include <system_error>

namespace hydra_multi {
namespace {

// The ordering by one method, with a cholmod_common of its own.
std::optional<FillReducingOrdering> orderBy(cholmod_sparse* pattern, OrderingMethod method) {
  cholmod_common common;
  cholmod_l_start(&common);
  common.print = 0;
  common.error_handler = nullptr;
  common.nmethods = 1;
  common.method[0].ordering = method == OrderingMethod::kAmd ? CHOLMOD_AMD : CHOLMOD_METIS;
  common.supernodal = CHOLMOD_SIMPLICIAL;  // the ordering and its counts only
  std::optional<FillReducingOrdering> ordering;
  if (cholmod_factor* L = cholmod_l_analyze(pattern, &common)) {
    const auto* perm = static_cast<const SuiteSparse_long*>(L->Perm);
    ordering =
        FillReducingOrdering{method, std::vector<long>(perm, perm + L->n), common.fl, common.lnz};
    cholmod_l_free_factor(&L, &common);
  }
  cholmod_l_finish(&common);
  return ordering;
}

}  // namespace

cholmod_sparse* patternMatrix(const std::vector<std::vector<long>>& rows, int stype,
                              cholmod_common& common) {
  const size_t n = rows.size();
  size_t entries = 0;
  for (const auto& column : rows) entries += column.size();
  cholmod_sparse* pattern = cholmod_l_allocate_sparse(n, n, entries, /*sorted=*/1, /*packed=*/1,
                                                      stype, CHOLMOD_PATTERN, &common);
  if (pattern == nullptr) return nullptr;
  auto* column_start = static_cast<SuiteSparse_long*>(pattern->p);
  auto* row_index = static_cast<SuiteSparse_long*>(pattern->i);
  long at = 0;
  for (size_t c = 0; c < n; ++c) {
    column_start[c] = at;
    for (const long r : rows[c]) row_index[at++] = r;
  }
  column_start[n] = at;
  return pattern;
}

std::optional<FillReducingOrdering> orderForCholesky(const std::vector<std::vector<long>>& rows,
                                                     size_t both_from,
                                                     std::optional<OrderingMethod> only) {
  const size_t n = rows.size();
  cholmod_common common;
  cholmod_l_start(&common);
  common.print = 0;
  common.error_handler = nullptr;
  cholmod_sparse* pattern = patternMatrix(rows, /*stype=*/1, common);
  std::optional<FillReducingOrdering> best;
  if (pattern != nullptr) {
    std::vector<OrderingMethod> methods;
    if (only) {
      methods.push_back(*only);
    } else {
      methods.push_back(OrderingMethod::kAmd);
      if (n >= both_from) methods.push_back(OrderingMethod::kMetis);
    }
    // Two methods at once where a second thread starts (each with its own cholmod_common; the
    // pattern only read): the same choice as one after the other.
    std::vector<std::optional<FillReducingOrdering>> orderings(methods.size());
    std::future<std::optional<FillReducingOrdering>> second;
    if (methods.size() > 1) {
      try {
        second = std::async(std::launch::async, orderBy, pattern, methods[1]);
      } catch (const std::system_error&) {  // no thread: in turn on this one
      }
    }
    orderings[0] = orderBy(pattern, methods[0]);
    if (methods.size() > 1)
      orderings[1] = second.valid() ? second.get() : orderBy(pattern, methods[1]);
    for (std::optional<FillReducingOrdering>& ordering : orderings) {
      if (ordering && (!best || ordering->flops < best->flops)) best = std::move(ordering);
    }
    cholmod_l_free_sparse(&pattern, &common);
  }
  cholmod_l_finish(&common);
  return best;
}

}  // namespace hydra_multi
