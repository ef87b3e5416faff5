#include "meso/core/warnings.h"

namespace meso {

Warnings& Warnings::operator=(Warnings&& other) noexcept {
  texts_ = std::move(other.texts_);
  return *this;
}

void Warnings::add(std::string text) {
  if (text.empty()) return;
  std::lock_guard lock(mutex_);
  texts_.push_back(std::move(text));
}

void Warnings::append(Warnings&& other) {
  std::vector<std::string> texts;
  {
    std::lock_guard lock(other.mutex_);
    texts.swap(other.texts_);
  }
  std::lock_guard lock(mutex_);
  texts_.insert(texts_.end(), std::make_move_iterator(texts.begin()),
                std::make_move_iterator(texts.end()));
}

std::vector<std::string> Warnings::list() const {
  std::lock_guard lock(mutex_);
  return texts_;
}

size_t Warnings::size() const {
  std::lock_guard lock(mutex_);
  return texts_.size();
}

}  // namespace meso
