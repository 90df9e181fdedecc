// A fixed-capacity FIFO (in the spirit of Pigweed's pw_containers and ETL's circular_buffer):
// std::array storage, no heap, every operation O(1). A push into a full queue is refused; the
// caller decides what is dropped and counts it.
#pragma once

#include <array>
#include <cstddef>

namespace fw {

template <class T, std::size_t Capacity>
class FixedQueue {
  static_assert(Capacity > 0, "a queue holds at least one element");

 public:
  static constexpr std::size_t capacity() { return Capacity; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == Capacity; }
  void clear() { head_ = size_ = 0; }

  bool push(const T& value) {
    T* slot = next_slot();
    if (slot == nullptr) return false;
    *slot = value;
    commit();
    return true;
  }
  // In two steps, for an element written in place: the slot the next push fills (nullptr when
  // the queue is full), then commit() to queue what was written there.
  T* next_slot() { return full() ? nullptr : &buffer_[slot(size_)]; }
  void commit() { ++size_; }

  bool pop(T& out) {
    if (empty()) return false;
    out = buffer_[head_];
    pop_front(1);
    return true;
  }
  // The oldest n elements dropped; n <= size().
  void pop_front(std::size_t n) {
    head_ = (head_ + n) % Capacity;
    size_ -= n;
  }
  // The newest element dropped; not empty.
  void pop_back() { --size_; }

  // The i-th element from the oldest; i < size().
  T& operator[](std::size_t i) { return buffer_[slot(i)]; }
  const T& operator[](std::size_t i) const { return buffer_[slot(i)]; }
  T& front() { return buffer_[head_]; }
  const T& front() const { return buffer_[head_]; }

 private:
  std::size_t slot(std::size_t i) const { return (head_ + i) % Capacity; }

  std::array<T, Capacity> buffer_{};
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace fw
