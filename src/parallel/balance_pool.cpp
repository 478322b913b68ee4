#include "fricrom/balance_pool.h"

#include <stdexcept>
#include <utility>

namespace fricrom {

BalancePool::BalancePool(const HarmonicBalance& first, BalanceMaker make)
    : first_(first), make_(std::move(make)) {}

BalancePool::Lease::Lease(BalancePool* pool, std::unique_ptr<HarmonicBalance> own)
    : pool_(pool), own_(std::move(own)) {}

BalancePool::Lease::~Lease() {
  const std::lock_guard<std::mutex> g(pool_->lock_);
  if (own_) {
    pool_->free_.push_back(std::move(own_));
  } else {
    pool_->first_free_ = true;
  }
}

BalancePool::Lease BalancePool::Borrow() {
  {
    const std::lock_guard<std::mutex> g(lock_);
    if (first_free_) {
      first_free_ = false;
      return Lease(this, nullptr);
    }
    if (!free_.empty()) {
      std::unique_ptr<HarmonicBalance> b = std::move(free_.back());
      free_.pop_back();
      return Lease(this, std::move(b));
    }
  }
  if (!make_)
    throw std::logic_error("BalancePool: a second balance is needed but there is no maker");
  std::unique_ptr<HarmonicBalance> b = make_();  // outside the lock: an FE balance takes a while
  if (!b) throw std::logic_error("BalancePool: the maker returned no balance");
  return Lease(this, std::move(b));
}

}  // namespace fricrom
