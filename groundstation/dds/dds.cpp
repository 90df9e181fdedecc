#include "groundstation/dds/dds.hpp"

#include <thread>

namespace gs::dds {
namespace {

[[noreturn]] void fail(const std::string& what, dds_return_t code) {
  throw DdsError(what + ": " + dds_strretcode(code));
}

dds_entity_t checked(dds_entity_t handle, const char* what) {
  if (handle < 0) fail(what, handle);
  return handle;
}

// A QoS object deleted at scope exit.
struct Qos {
  explicit Qos(const TopicQos& qos) : qos_(make_qos(qos)) {}
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
  ~Qos() { dds_delete_qos(qos_); }
  dds_qos_t* qos_;
};

}  // namespace

std::string loopback_config() {
  // Multicast off: discovery goes by unicast to the peer list (localhost), trying participant
  // indices 0..MaxAutoParticipantIndex, one per process on the host.
  return "<CycloneDDS><Domain Id=\"any\">"
         "<General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
         "<AllowMulticast>false</AllowMulticast></General>"
         "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
         "<MaxAutoParticipantIndex>20</MaxAutoParticipantIndex>"
         "<Peers><Peer Address=\"127.0.0.1\"/></Peers></Discovery>"
         "</Domain></CycloneDDS>";
}

std::string in_process_config() {
  // No multicast, no peers, no fixed participant index: nobody outside can find it.
  return "<CycloneDDS><Domain Id=\"any\">"
         "<General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
         "<AllowMulticast>false</AllowMulticast></General>"
         "<Discovery><ParticipantIndex>none</ParticipantIndex></Discovery>"
         "</Domain></CycloneDDS>";
}

Entity& Entity::operator=(Entity&& other) noexcept {
  if (this != &other) {
    reset();
    handle_ = other.release();
  }
  return *this;
}

dds_entity_t Entity::release() {
  const dds_entity_t handle = handle_;
  handle_ = 0;
  return handle;
}

void Entity::reset() {
  // The entity may be gone already with its parent (a domain deleted first): the call then fails
  // harmlessly.
  if (handle_ > 0) dds_delete(handle_);
  handle_ = 0;
}

Domain::Domain(dds_domainid_t id, const std::string& config)
    : id_(id), domain_(checked(dds_create_domain(id, config.c_str()), "dds_create_domain")) {}

Participant::Participant(const Domain& domain)
    : participant_(checked(dds_create_participant(domain.id(), nullptr, nullptr), "dds_create_participant")) {
}

dds_qos_t* make_qos(const TopicQos& qos) {
  dds_qos_t* q = dds_create_qos();
  const bool reliable = qos.delivery != Delivery::latest;
  dds_qset_reliability(q, reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT, DDS_MSECS(100));
  dds_qset_history(q, DDS_HISTORY_KEEP_LAST, qos.depth);
  if (qos.delivery == Delivery::history) {
    dds_qset_durability(q, DDS_DURABILITY_TRANSIENT_LOCAL);
    // What a writer keeps for late joiners is the durability service's history (Cyclone's
    // default: the last 1), not the writer's.
    dds_qset_durability_service(q, 0, DDS_HISTORY_KEEP_LAST, qos.depth, DDS_LENGTH_UNLIMITED,
                                DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  } else {
    dds_qset_durability(q, DDS_DURABILITY_VOLATILE);
  }
  return q;
}

namespace detail {

Entity create_topic(const Participant& participant, const char* name,
                    const dds_topic_descriptor_t* descriptor, const TopicQos& qos) {
  const Qos q(qos);
  return Entity(
      checked(dds_create_topic(participant.get(), descriptor, name, q.qos_, nullptr), "dds_create_topic"));
}

Entity create_writer(const Participant& participant, const Entity& topic, const TopicQos& qos) {
  const Qos q(qos);
  return Entity(
      checked(dds_create_writer(participant.get(), topic.get(), q.qos_, nullptr), "dds_create_writer"));
}

Entity create_reader(const Participant& participant, const Entity& topic, const TopicQos& qos) {
  const Qos q(qos);
  return Entity(
      checked(dds_create_reader(participant.get(), topic.get(), q.qos_, nullptr), "dds_create_reader"));
}

void write(const Entity& writer, const void* sample) {
  const dds_return_t rc = dds_write(writer.get(), sample);
  if (rc < 0) fail("dds_write", rc);
}

std::uint32_t matched_readers(const Entity& writer) {
  dds_publication_matched_status_t status{};
  const dds_return_t rc = dds_get_publication_matched_status(writer.get(), &status);
  if (rc < 0) fail("dds_get_publication_matched_status", rc);
  return status.current_count;
}

std::uint32_t matched_writers(const Entity& reader) {
  dds_subscription_matched_status_t status{};
  const dds_return_t rc = dds_get_subscription_matched_status(reader.get(), &status);
  if (rc < 0) fail("dds_get_subscription_matched_status", rc);
  return status.current_count;
}

void sleep_briefly() { std::this_thread::sleep_for(std::chrono::milliseconds(5)); }

ReaderCore::ReaderCore(const Participant& participant, Entity reader,
                       const dds_topic_descriptor_t* descriptor, void* sample)
    : reader_(std::move(reader)),
      condition_(checked(dds_create_readcondition(reader_.get(), DDS_ANY_STATE), "dds_create_readcondition")),
      waitset_(checked(dds_create_waitset(participant.get()), "dds_create_waitset")),
      descriptor_(descriptor),
      sample_(sample) {
  const dds_return_t rc = dds_waitset_attach(waitset_.get(), condition_.get(), 0);
  if (rc < 0) fail("dds_waitset_attach", rc);
}

ReaderCore::~ReaderCore() {
  // What Cyclone allocated inside the sample (sequence buffers); the sample itself is the
  // Reader's member.
  dds_sample_free(sample_, descriptor_, DDS_FREE_CONTENTS);
  waitset_.reset();
  condition_.reset();
  reader_.reset();
}

bool ReaderCore::take() {
  for (;;) {
    void* samples[1] = {sample_};
    dds_sample_info_t info{};
    const dds_return_t n = dds_take(condition_.get(), samples, &info, 1, 1);
    if (n < 0) fail("dds_take", n);
    if (n == 0) return false;
    if (info.valid_data) return true;
  }
}

bool ReaderCore::wait_take(std::chrono::nanoseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (take()) return true;
    const auto left = end - std::chrono::steady_clock::now();
    if (left <= std::chrono::nanoseconds::zero()) return false;
    const dds_return_t rc =
        dds_waitset_wait(waitset_.get(), nullptr, 0, static_cast<dds_duration_t>(left.count()));
    if (rc < 0) fail("dds_waitset_wait", rc);
  }
}

}  // namespace detail
}  // namespace gs::dds
