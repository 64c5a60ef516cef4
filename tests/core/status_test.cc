// Tests of ROLLWEAR_RETURN_IF_ERROR and ROLLWEAR_ASSIGN_OR_RETURN
// (core/base/status.h): the value flows through on success, an error comes
// back unchanged (code and message), move-only values work, and several uses
// in one scope do not collide; `*std::move(s)` moves the value out.
#include "core/base/status.h"

#include <map>
#include <memory>
#include <string>
#include <utility>

#include <gtest/gtest.h>

namespace rollwear {
namespace {

StatusOr<int> Half(int x) {
  if (x % 2 != 0) {
    return Status::InvalidArgument(
        "coils.csv:3:7 width_mm: " + std::to_string(x) + " is odd");
  }
  return x / 2;
}

Status CheckPositive(int x) {
  if (x <= 0) return Status::FailedPrecondition("x must be > 0");
  return Status::Ok();
}

// Two ASSIGN_OR_RETURN in one scope: the temporaries must not collide.
StatusOr<int> Quarter(int x) {
  ROLLWEAR_ASSIGN_OR_RETURN(int h, Half(x));
  ROLLWEAR_ASSIGN_OR_RETURN(int q, Half(h));
  return q;
}

Status QuarterPositive(int x, int* out) {
  ROLLWEAR_RETURN_IF_ERROR(CheckPositive(x));
  ROLLWEAR_ASSIGN_OR_RETURN(*out, Quarter(x));  // assigns an existing lvalue
  ROLLWEAR_RETURN_IF_ERROR(CheckPositive(*out - 1));  // quarter > 1
  return Status::Ok();
}

StatusOr<std::unique_ptr<int>> MakeBox(int v) {
  if (v < 0) return Status::NotFound("no box for " + std::to_string(v));
  return std::make_unique<int>(v);
}

StatusOr<std::unique_ptr<int>> BoxPlusOne(int v) {
  ROLLWEAR_ASSIGN_OR_RETURN(std::unique_ptr<int> box, MakeBox(v));
  ++*box;
  return box;
}

// `expr` with a comma inside template arguments.
StatusOr<std::map<int, int>> MakeMap(bool ok) {
  if (!ok) return Status::Internal("map");
  return std::map<int, int>{{1, 2}};
}

StatusOr<int> MapSize(bool ok) {
  ROLLWEAR_ASSIGN_OR_RETURN(auto m, MakeMap(ok));
  return static_cast<int>(m.size()) + m.at(1);
}

TEST(StatusMacros, AssignOrReturnPassesTheValue) {
  StatusOr<int> q = Quarter(12);
  ASSERT_TRUE(q.ok());
  EXPECT_EQ(*q, 3);
  StatusOr<int> m = MapSize(true);
  ASSERT_TRUE(m.ok());
  EXPECT_EQ(*m, 3);
}

TEST(StatusMacros, AssignOrReturnPropagatesTheErrorUnchanged) {
  StatusOr<int> first = Quarter(7);  // fails in the first Half
  ASSERT_FALSE(first.ok());
  EXPECT_EQ(first.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(first.status().message(), "coils.csv:3:7 width_mm: 7 is odd");
  StatusOr<int> second = Quarter(6);  // fails in the second Half
  ASSERT_FALSE(second.ok());
  EXPECT_EQ(second.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(second.status().message(), "coils.csv:3:7 width_mm: 3 is odd");
  StatusOr<int> m = MapSize(false);
  ASSERT_FALSE(m.ok());
  EXPECT_EQ(m.status().code(), StatusCode::kInternal);
  EXPECT_EQ(m.status().message(), "map");
}

TEST(StatusMacros, ReturnIfErrorAndAssignIntoStatusFunction) {
  int out = -1;
  EXPECT_TRUE(QuarterPositive(8, &out).ok());
  EXPECT_EQ(out, 2);

  out = -1;
  Status neg = QuarterPositive(-4, &out);
  EXPECT_EQ(neg.code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(neg.message(), "x must be > 0");
  EXPECT_EQ(out, -1);  // returned before the assignment

  Status odd = QuarterPositive(10, &out);
  EXPECT_EQ(odd.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(odd.message(), "coils.csv:3:7 width_mm: 5 is odd");
  EXPECT_EQ(out, -1);

  Status one = QuarterPositive(4, &out);  // assigned 1, fails the last check
  EXPECT_EQ(one.code(), StatusCode::kFailedPrecondition);
  EXPECT_EQ(one.message(), "x must be > 0");
  EXPECT_EQ(out, 1);
}

TEST(StatusMacros, AssignOrReturnMovesMoveOnlyValues) {
  StatusOr<std::unique_ptr<int>> box = BoxPlusOne(41);
  ASSERT_TRUE(box.ok());
  ASSERT_NE(box->get(), nullptr);
  EXPECT_EQ(**box, 42);

  StatusOr<std::unique_ptr<int>> none = BoxPlusOne(-1);
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.status().code(), StatusCode::kNotFound);
  EXPECT_EQ(none.status().message(), "no box for -1");
}

// `*std::move(s)` moves the value out, as `std::move(s).value()` does: a
// move-only value can be taken that way, and a copyable one is not copied
// (it used to bind to the const& overload and copy, a whole Dataset in the
// file-reading tools).
TEST(StatusOrTest, DereferencingAnRvalueMovesTheValueOut) {
  StatusOr<std::unique_ptr<int>> box = BoxPlusOne(1);
  ASSERT_TRUE(box.ok());
  std::unique_ptr<int> taken = *std::move(box);
  ASSERT_NE(taken, nullptr);
  EXPECT_EQ(*taken, 2);

  struct Counted {
    int* copies;
    Counted(int* c) : copies(c) {}  // NOLINT
    Counted(const Counted& o) : copies(o.copies) { ++*copies; }
    Counted(Counted&&) = default;
  };
  int copies = 0;
  StatusOr<Counted> counted(Counted{&copies});
  copies = 0;
  Counted out = *std::move(counted);
  EXPECT_EQ(copies, 0);
  EXPECT_EQ(out.copies, &copies);
}

}  // namespace
}  // namespace rollwear
