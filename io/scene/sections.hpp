// The scene's sections: each is its key table (io/scene/keys.hpp) with the rules that tie its keys together,
// and how it is read, written into the resolved scene and documented. reader.cpp composes them in order.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "io/scene/keys.hpp"

namespace vitrum::scene_io {

/// One section of the scene file: a table [name] or an array of tables [[name]].
struct Section {
    std::string name;
    bool array = false;
    std::string meaning; ///< a paragraph for the reference
    /// Reads it from r.top into r.scene, checking its keys and the rules between them.
    std::function<void(SceneReading& r)> read;
    /// Appends its blocks of the resolved scene ("[name]\nkey = value\n"; none where the scene has none).
    std::function<void(const Scene& scene, const Units& units, std::vector<std::string>& blocks)> write;
    std::function<std::vector<KeyDoc>()> docs;
};

/// The part of the scene a section fills: member<&Scene::sample>, or the whole scene ([scene], [effects]).
template <auto M> constexpr auto member = [](auto& scene) -> auto& {
    return scene.*M;
};
constexpr auto wholeScene = [](auto& scene) -> auto& {
    return scene;
};

/// A section that is one struct of the scene read by its table alone.
template <class S, class Part>
Section plainSection(std::string name, std::string meaning, Part part, const std::vector<Key<S>>& (*keys)()) {
    Section s;
    s.name = name;
    s.meaning = std::move(meaning);
    s.read = [name, part, keys](SceneReading& r) {
        readKeys(r.top.subtable(name), keys(), part(r.scene), r);
    };
    s.write = [name, part, keys](const Scene& scene, const Units& units, std::vector<std::string>& blocks) {
        std::string out = "[" + name + "]\n";
        writeKeys(out, keys(), part(scene), units);
        blocks.push_back(out);
    };
    s.docs = [keys]() { return keyDocs(keys()); };
    return s;
}

/// For the table of an effect's parameters: refuses it when the effect is not in effects.list. Returns
/// whether the effect is on (and so the table is to be read).
bool effectTable(const TableReader& table, const Scene& scene, Effect effect);

/// Every section, in the order of the resolved scene and of reading (reader.cpp).
const std::vector<Section>& sceneSections();

// sections_sample.cpp
Section sceneSection();
Section unitsSection();
Section effectsSection();
Section sampleSection();
Section materialSection();
Section setsSection();
// sections_loads.cpp
Section boundarySection();
Section loadSection();
Section dampingSection();
Section timeSection();
Section precisionSection();
Section measureSection();
Section outputSection();
// sections_effects.cpp
Section densificationSection();
Section plasticitySection();
Section fractureSection();
Section contactSection();
Section couplingSection();
// sections_indenter.cpp
Section indenterSection();
Section stageSection();

} // namespace vitrum::scene_io
