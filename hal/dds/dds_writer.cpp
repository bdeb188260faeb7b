#include "dds_writer.hpp"

#include "qos.hpp"
#include "ros2_names.hpp"

namespace sinew::hal::dds {

bool DdsWriter::open(uint32_t domain_id, const std::string& ros_namespace, const std::string& topic,
                     const dds_topic_descriptor_t* type, dds_qos_t* qos, std::string* error) {
  const auto fail = [&](std::string why) {
    dds_delete_qos(qos);
    *error = std::move(why);
    return false;
  };
  if (!ros2_topic_name(ros_namespace, topic, &dds_topic_, error)) return fail(*error);
  if (domain_id > kMaxDomainId) return fail("domain_id " + std::to_string(domain_id) + " is beyond 232");
  participant_ = DdsEntity(dds_create_participant(domain_id, nullptr, nullptr));
  if (!participant_.valid())
    return fail("DDS participant on domain " + std::to_string(domain_id) + ": " + dds_error_text(participant_.get()));
  topic_ = DdsEntity(dds_create_topic(participant_.get(), type, dds_topic_.c_str(), nullptr, nullptr));
  if (!topic_.valid()) return fail("DDS topic " + dds_topic_ + ": " + dds_error_text(topic_.get()));
  writer_ = DdsEntity(dds_create_writer(participant_.get(), topic_.get(), qos, nullptr));
  dds_delete_qos(qos);
  if (!writer_.valid()) return *error = "DDS writer on " + dds_topic_ + ": " + dds_error_text(writer_.get()), false;
  return true;
}

uint32_t DdsWriter::matched_readers() const {
  dds_publication_matched_status_t matched{};
  if (!writer_.valid() || dds_get_publication_matched_status(writer_.get(), &matched) != DDS_RETCODE_OK) return 0;
  return matched.current_count;
}

Ros2Time ros2_time(int64_t ns) {
  const int64_t sec = ns >= 0 ? ns / 1'000'000'000 : (ns - 999'999'999) / 1'000'000'000;
  return {static_cast<int32_t>(sec), static_cast<uint32_t>(ns - sec * 1'000'000'000)};
}

}  // namespace sinew::hal::dds
