// Balances for worker threads: a HarmonicBalance caches per-frequency data (factorisations,
// workspaces), so two threads never use one at the same time. The pool lends the caller's balance
// to one thread and builds one more per extra thread, on first need, with the given maker.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "fricrom/harmonic_balance.h"

namespace fricrom {

using BalanceMaker = std::function<std::unique_ptr<HarmonicBalance>()>;

class BalancePool {
 public:
  // `first` must outlive the pool; `make` may be empty when only one thread ever borrows.
  BalancePool(const HarmonicBalance& first, BalanceMaker make);

  // A balance for the calling thread until the lease ends.
  class Lease {
   public:
    ~Lease();
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    const HarmonicBalance& get() const { return own_ ? *own_ : pool_->first_; }

   private:
    friend class BalancePool;
    Lease(BalancePool* pool, std::unique_ptr<HarmonicBalance> own);
    BalancePool* pool_;
    std::unique_ptr<HarmonicBalance> own_;  // null: the pool's first balance
  };
  // Throws std::logic_error when a second balance is needed and there is no maker.
  Lease Borrow();

 private:
  const HarmonicBalance& first_;
  BalanceMaker make_;
  std::mutex lock_;
  bool first_free_ = true;
  std::vector<std::unique_ptr<HarmonicBalance>> free_;
};

}  // namespace fricrom
