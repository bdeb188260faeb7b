// The loaders' error messages, naming the section, its instance and field.
#include "section_view.hpp"

#include "sim_core/rig/message.hpp"

namespace sinew::pipeline {
namespace {

const char* section_name(uint32_t id) {
  const layer::SectionDescriptor* d = find_layer_section(id);
  return d != nullptr ? d->name : nullptr;
}

}  // namespace

rig::LoadStatus section_fail(rig::LoadError e, uint32_t id, uint32_t instance, const char* field, int64_t index,
                             const char* what, int64_t value, bool show_value) {
  rig::LoadStatus s;
  s.error = e;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text("rig blob: ").text(section_name(id)).text("#").number(instance);
  if (field != nullptr && *field != '\0') m.text(".").text(field);
  if (index >= 0) m.text("[").number(index).text("]");
  m.text(": ").text(what);
  if (show_value) m.text(" (").number(value).text(")");
  return s;
}

rig::LoadStatus section_layer_fail(rig::LoadError e, const SectionView& v, const char* message) {
  rig::LoadStatus s;
  s.error = e;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text("rig blob: ").text(section_name(v.id)).text("#").number(v.instance).text(": ").text(message);
  return s;
}

}  // namespace sinew::pipeline
