// A fixed-capacity single-producer single-consumer ring for passing frames between an
// interrupt handler and the main loop without locks: each index is written by one side only,
// and the release/acquire pair orders the slot's contents before the index that publishes it.
// Free-running 32-bit indices, so full and empty are told apart without a spare slot.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace stm32f405 {

template <class T, std::size_t Capacity>
class SpscRing {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "capacity must be a power of two");
  static_assert(std::atomic<std::uint32_t>::is_always_lock_free);

 public:
  // Producer side. Returns false (and drops `item`) when the ring is full.
  bool push(const T& item) {
    const std::uint32_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= Capacity) return false;
    slots_[head & (Capacity - 1)] = item;
    head_.store(head + 1u, std::memory_order_release);
    return true;
  }

  // Consumer side. Returns false when the ring is empty.
  bool pop(T& out) {
    const std::uint32_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) return false;
    out = slots_[tail & (Capacity - 1)];
    tail_.store(tail + 1u, std::memory_order_release);
    return true;
  }

  // Either side; exact only on the consumer side (the producer may add meanwhile).
  bool empty() const {
    return head_.load(std::memory_order_acquire) == tail_.load(std::memory_order_acquire);
  }

 private:
  std::array<T, Capacity> slots_{};
  std::atomic<std::uint32_t> head_{0};
  std::atomic<std::uint32_t> tail_{0};
};

}  // namespace stm32f405
