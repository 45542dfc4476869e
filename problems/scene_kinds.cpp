#include "problems/scene_kinds.hpp"

#include <deque>
#include <filesystem>
#include <stdexcept>

#include "problems/scene_node.hpp"

namespace tailor {
namespace {

// Verbs and kinds; tailor's own are added on first use (not by static initializers, which a
// static library may drop and whose order between files is unspecified).
class Registry {
 public:
  Registry() {
    for (Verb& verb : builtin_verbs()) add_verb(std::move(verb));
    for (SceneKind& kind : builtin_scene_kinds()) add_kind(std::move(kind), builtin_kinds_);
    if (builtin_kinds_.empty()) throw std::logic_error("tailor registers no scene kind");
  }

  void add_verb(Verb verb) {
    if (verb.name.empty() || verb.name[0] == '-')
      throw std::logic_error("a verb needs a name not starting with '-'");
    if (find_verb(verb.name)) throw std::logic_error("the verb '" + verb.name + "' is registered twice");
    verbs_.push_back(std::move(verb));
  }

  // A program's kinds go before tailor's (whose last kind is the default, matching anything).
  void add_user_kind(SceneKind kind) { add_kind(std::move(kind), user_kinds_); }

  const Verb* find_verb(const std::string& name) const {
    for (const Verb& verb : verbs_)
      if (verb.name == name) return &verb;
    return nullptr;
  }

  std::vector<const Verb*> verbs() const {
    std::vector<const Verb*> all;
    for (const Verb& verb : verbs_) all.push_back(&verb);
    return all;
  }

  std::vector<const SceneKind*> kinds() const {
    std::vector<const SceneKind*> all;
    for (const SceneKind& kind : user_kinds_) all.push_back(&kind);
    for (const SceneKind& kind : builtin_kinds_) all.push_back(&kind);
    return all;
  }

  const SceneKind& default_kind() const { return builtin_kinds_.back(); }

 private:
  void add_kind(SceneKind kind, std::deque<SceneKind>& into) {
    const std::string what = "scene kind '" + kind.name + "'";
    if (kind.name.empty()) throw std::logic_error("a scene kind needs a name");
    for (const SceneKind* other : kinds())
      if (other->name == kind.name) throw std::logic_error("the " + what + " is registered twice");
    if (!kind.recognises) throw std::logic_error("the " + what + " needs a `recognises` function");
    if (kind.verbs.empty()) throw std::logic_error("the " + what + " supports no verb");
    for (const KindVerb& entry : kind.verbs) {
      if (!find_verb(entry.verb)) {
        std::string known;
        for (const Verb& verb : verbs_) known += (known.empty() ? "" : ", ") + verb.name;
        throw std::logic_error("the " + what + " names the verb '" + entry.verb +
                               "', which is not registered (register it first; registered: " + known + ")");
      }
      if (!entry.handler) throw std::logic_error("the " + what + " has no handler for '" + entry.verb + "'");
      int count = 0;
      for (const KindVerb& other : kind.verbs) count += other.verb == entry.verb;
      if (count > 1) throw std::logic_error("the " + what + " lists the verb '" + entry.verb + "' twice");
    }
    into.push_back(std::move(kind));
  }

  // Deques: a registration must not move the entries that earlier lookups point to.
  std::deque<Verb> verbs_;
  std::deque<SceneKind> user_kinds_, builtin_kinds_;
};

Registry& registry() {
  static Registry instance;
  return instance;
}

}  // namespace

SceneNode SceneFile::node() const { return SceneNode(document, source, ""); }

std::string SceneFile::directory() const {
  return path.empty() ? base_directory : std::filesystem::path(path).parent_path().string();
}

std::string SceneFile::stem() const {
  return path.empty() ? std::string("scene") : std::filesystem::path(path).stem().string();
}

std::string SceneFile::name() const {
  if (document.is_object() && document.contains("name") && document["name"].is_string() &&
      !document["name"].get<std::string>().empty())
    return document["name"].get<std::string>();
  return stem();
}

std::string SceneFile::default_out_dir() const { return "out/" + name(); }

SceneFile read_scene_file(const std::string& path) {
  SceneFile file;
  file.path = file.source = path;
  file.document = read_scene_document(path);
  return file;
}

SceneFile scene_from_text(const std::string& json_text, const std::string& source,
                          const std::string& directory) {
  const std::string name = source.empty() ? std::string("(scene)") : source;
  return scene_from_document(parse_scene_document(json_text, name), name, directory);
}

SceneFile scene_from_document(nlohmann::json document, const std::string& source,
                              const std::string& directory) {
  SceneFile file;
  file.source = source.empty() ? std::string("(scene)") : source;
  file.document = std::move(document);
  file.base_directory = directory;
  return file;
}

const KindVerb* SceneKind::find_verb(const std::string& verb) const {
  for (const KindVerb& entry : verbs)
    if (entry.verb == verb) return &entry;
  return nullptr;
}

std::string SceneKind::verb_list() const {
  std::string list;
  for (const KindVerb& entry : verbs) list += (list.empty() ? "" : ", ") + entry.verb;
  return list;
}

void register_verb(Verb verb) { registry().add_verb(std::move(verb)); }

void register_scene_kind(SceneKind kind) { registry().add_user_kind(std::move(kind)); }

std::vector<const Verb*> registered_verbs() { return registry().verbs(); }

const Verb* find_verb(const std::string& name) { return registry().find_verb(name); }

std::vector<const SceneKind*> registered_scene_kinds() { return registry().kinds(); }

const SceneKind& recognise_scene_kind(const nlohmann::json& document) {
  for (const SceneKind* kind : registry().kinds())
    if (kind->recognises(document)) return *kind;
  return registry().default_kind();
}

const SceneKind& default_scene_kind() { return registry().default_kind(); }

void apply_thread_flags(const VerbArguments& args, const std::optional<ThreadSettings>& scene_threads) {
  ThreadSettings threads = scene_threads.value_or(thread_settings());
  if (args.threads) threads.assembly = threads.blas = *args.threads;
  if (args.factorization_threads) threads.factorization = *args.factorization_threads;
  set_thread_settings(threads);
}

}  // namespace tailor
