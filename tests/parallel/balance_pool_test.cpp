#include "fricrom/balance_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <set>
#include <stdexcept>

#include "fricrom/hbm_system.h"
#include "fricrom/work_queue.h"
#include "test_models.h"

namespace fricrom {
namespace {

// The first borrower gets the caller's balance; concurrent borrowers never share one, and extra
// balances are built only as needed and reused.
TEST(BalancePool, LendsEachBalanceToOneThreadAtATime) {
  const Model model = testing::LoadBaseline().model;
  HbmSystem first(model, HbmOptions{1, 64});
  int made = 0;
  BalancePool pool(first, [&] {
    ++made;
    return std::make_unique<HbmSystem>(model, HbmOptions{1, 64});
  });
  {
    const BalancePool::Lease a = pool.Borrow();
    EXPECT_EQ(&a.get(), &first);
    const BalancePool::Lease b = pool.Borrow();
    EXPECT_NE(&b.get(), &first);
    EXPECT_EQ(made, 1);
  }
  {
    const BalancePool::Lease a = pool.Borrow();
    const BalancePool::Lease b = pool.Borrow();
    EXPECT_NE(&a.get(), &b.get());
    EXPECT_EQ(made, 1);  // returned balances are lent again
  }
  std::mutex lock;
  std::set<const HarmonicBalance*> in_use;
  std::atomic<int> clashes{0};
  std::vector<int> units(40);
  for (int i = 0; i < 40; ++i) units[i] = i;
  RunWorkUnits(
      units, 2,
      [&](int) {
        const BalancePool::Lease l = pool.Borrow();
        {
          const std::lock_guard<std::mutex> g(lock);
          clashes += !in_use.insert(&l.get()).second;
        }
        const std::lock_guard<std::mutex> g(lock);
        in_use.erase(&l.get());
      },
      [](int) {});
  EXPECT_EQ(clashes.load(), 0);
  EXPECT_LE(made, 2);
}

TEST(BalancePool, ASecondBalanceWithoutAMakerIsAnError) {
  HbmSystem first(testing::LoadBaseline().model, HbmOptions{1, 64});
  BalancePool pool(first, {});
  const BalancePool::Lease a = pool.Borrow();
  EXPECT_THROW(pool.Borrow(), std::logic_error);
}

}  // namespace
}  // namespace fricrom
