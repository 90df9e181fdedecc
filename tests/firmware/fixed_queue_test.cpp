// The firmware's one bounded FIFO (the transmit queue, the command queue, the link guard's queue).
#include <catch2/catch.hpp>

#include <cstdint>

#include "fw/fixed_queue.hpp"

namespace {

using Queue = fw::FixedQueue<int, 3>;

}  // namespace

TEST_CASE("a fixed queue keeps order, refuses what does not fit and wraps around") {
  Queue q;
  CHECK(q.empty());
  CHECK(Queue::capacity() == 3);
  for (int i = 0; i < 5; ++i) CHECK(q.push(i) == (i < 3));
  CHECK(q.full());
  CHECK(q.size() == 3);
  int out = -1;
  // Around the end of the storage several times: what comes out is what went in, in order.
  for (int i = 0; i < 10; ++i) {
    REQUIRE(q.pop(out));
    CHECK(out == i);
    CHECK(q.push(i + 3));
    CHECK(q.front() == i + 1);
  }
  for (int i = 10; i < 13; ++i) {
    REQUIRE(q.pop(out));
    CHECK(out == i);
  }
  CHECK_FALSE(q.pop(out));
  CHECK(out == 12);  // a failed pop leaves its output alone
}

TEST_CASE("a fixed queue is indexed from its oldest element and dropped from either end") {
  Queue q;
  q.push(0);
  q.push(1);
  int out = 0;
  q.pop(out);
  q.push(2);
  q.push(3);  // the storage has wrapped: 1, 2, 3 with the oldest at slot 1
  CHECK(q[0] == 1);
  CHECK(q[1] == 2);
  CHECK(q[2] == 3);
  q[1] = 20;
  q.pop_back();
  CHECK(q.size() == 2);
  CHECK(q.push(4));
  q.pop_front(2);
  REQUIRE(q.size() == 1);
  CHECK(q.front() == 4);
  q.clear();
  CHECK(q.empty());
  CHECK_FALSE(q.pop(out));
}

TEST_CASE("an element is written in place through next_slot and queued by commit") {
  fw::FixedQueue<std::uint32_t, 2> q;
  std::uint32_t* slot = q.next_slot();
  REQUIRE(slot != nullptr);
  *slot = 7;
  CHECK(q.empty());  // not queued until committed
  q.commit();
  q.push(8);
  CHECK(q.next_slot() == nullptr);
  std::uint32_t out = 0;
  REQUIRE(q.pop(out));
  CHECK(out == 7);
}
