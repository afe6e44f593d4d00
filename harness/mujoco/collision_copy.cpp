// What a collision copy keeps of a model's geometry (collision_copy.hpp).
#include "mujoco/collision_copy.hpp"

#include <set>

namespace lowpair::mujoco::detail {

namespace {

namespace fs = std::filesystem;
using tinyxml2::XMLElement;

std::string attr(const XMLElement* e, const char* name) {
  const char* v = e->Attribute(name);
  return v ? v : "";
}

bool named(const XMLElement* e, const char* name) { return std::string(e->Name()) == name; }

// The folder a relative mesh file is read from: the last compiler setting of meshdir, else assetdir.
fs::path meshFolder(const XMLElement* block, const fs::path& folder) {
  std::string dir;
  for (const XMLElement* c = block->FirstChildElement("compiler"); c; c = c->NextSiblingElement("compiler")) {
    if (c->Attribute("meshdir")) {
      dir = attr(c, "meshdir");
    } else if (c->Attribute("assetdir") && dir.empty()) {
      dir = attr(c, "assetdir");
    }
  }
  const fs::path d(dir);
  return d.is_absolute() ? d : folder / d;
}

// A mesh file as an absolute path when it exists; "" when it does not (or is a package:// URI).
std::string existingFile(const std::string& file, const fs::path& mesh_folder) {
  if (file.rfind("package://", 0) == 0) return "";
  const fs::path p = fs::path(file).is_absolute() ? fs::path(file) : mesh_folder / file;
  std::error_code ec;
  return fs::is_regular_file(p, ec) ? fs::absolute(p).lexically_normal().string() : "";
}

// Calls f on every element below e (children before their parent), f may delete the element it is given.
void forEachBelow(XMLElement* e, const std::function<void(XMLElement*)>& f) {
  for (XMLElement* c = e->FirstChildElement(); c;) {
    XMLElement* next = c->NextSiblingElement();
    forEachBelow(c, f);
    f(c);
    c = next;
  }
}

}  // namespace

void keepMjcfCollisionGeometry(XMLElement* root, const fs::path& folder, const ElementOrigin& where,
                               std::vector<std::string>& notes) {
  const fs::path mesh_folder = meshFolder(root, folder);
  std::set<std::string> missing_meshes, dropped_geoms;
  for (XMLElement* asset = root->FirstChildElement("asset"); asset; asset = asset->NextSiblingElement("asset")) {
    for (XMLElement* c = asset->FirstChildElement(); c;) {
      XMLElement* next = c->NextSiblingElement();
      if (!named(c, "mesh")) {
        asset->DeleteChild(c);  // textures, materials, height fields, skins: no collision reads them
      } else if (c->Attribute("file")) {
        const std::string file = attr(c, "file");
        const std::string found = existingFile(file, mesh_folder);
        if (found.empty()) {
          // MuJoCo names an unnamed mesh after its file's stem
          missing_meshes.insert(c->Attribute("name") ? attr(c, "name") : fs::path(file).stem().string());
          notes.push_back(where(c) + ": mesh file '" + file + "' not found: its geoms are not checked for collisions");
          asset->DeleteChild(c);
        } else {
          c->SetAttribute("file", found.c_str());
        }
      }
      c = next;
    }
  }
  forEachBelow(root, [&](XMLElement* e) {
    if (!named(e, "geom")) return;
    e->DeleteAttribute("material");
    const bool parent_is_default = named(e->Parent()->ToElement(), "default");
    if (!parent_is_default && (missing_meshes.count(attr(e, "mesh")) || attr(e, "type") == "hfield")) {
      if (e->Attribute("name")) dropped_geoms.insert(attr(e, "name"));
      e->Parent()->DeleteChild(e);
    }
  });
  for (XMLElement* contact = root->FirstChildElement("contact"); contact;
       contact = contact->NextSiblingElement("contact")) {
    for (XMLElement* c = contact->FirstChildElement("pair"); c;) {
      XMLElement* next = c->NextSiblingElement("pair");
      if (dropped_geoms.count(attr(c, "geom1")) || dropped_geoms.count(attr(c, "geom2"))) contact->DeleteChild(c);
      c = next;
    }
  }
}

void keepUrdfCollisionGeometry(XMLElement* robot, const fs::path& folder, const ElementOrigin& where,
                               std::vector<std::string>& notes) {
  const XMLElement* block = robot->FirstChildElement("mujoco");
  const fs::path mesh_folder = block ? meshFolder(block, folder) : folder;
  for (XMLElement* link = robot->FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
    for (XMLElement* c = link->FirstChildElement("collision"); c;) {
      XMLElement* next = c->NextSiblingElement("collision");
      XMLElement* geometry = c->FirstChildElement("geometry");
      XMLElement* mesh = geometry ? geometry->FirstChildElement("mesh") : nullptr;
      if (mesh) {
        const std::string file = attr(mesh, "filename");
        const std::string found = existingFile(file, mesh_folder);
        if (found.empty()) {
          notes.push_back(where(mesh) + ": mesh '" + file + "' not found: link '" + attr(link, "name") +
                          "' has a collision geometry that is not checked");
          link->DeleteChild(c);
        } else {
          mesh->SetAttribute("filename", found.c_str());
        }
      }
      c = next;
    }
  }
}

}  // namespace lowpair::mujoco::detail
