#include "topic_sink.hpp"

#include "dds_writer.hpp"

namespace sinew::hal::dds {

TopicSink::TopicSink(std::string name, std::string type)
    : writer_(std::make_unique<DdsWriter>()), name_(std::move(name)), type_(std::move(type)) {}
TopicSink::~TopicSink() = default;

const std::string& TopicSink::dds_topic() const { return writer_->dds_topic(); }

uint32_t TopicSink::matched_readers() const { return writer_->matched_readers(); }

bool TopicSink::publish(const void* sample) {
  if (!writer_->write(sample)) return reject();
  ++written_;
  return true;
}

std::string TopicSink::status_line() const {
  return "dds " + dds_topic() + " (" + type_ + "): " + std::to_string(written_) + " written, " +
         std::to_string(failed_) + " failed, " + std::to_string(matched_readers()) + " readers matched";
}

}  // namespace sinew::hal::dds
