// What a finished scene holds, walked over on the host: its input segment
// count, whether it has aliased paths, and a text dump for tests.
#pragma once
#include <cstddef>
#include <string>

#include "core/scene.h"

namespace mpvg {

// Number of input segments over all path instances (an instance counts its
// geometry again), plus the closing lines that fills add.
size_t segment_count(const Scene& scene);

// A text dump of a scene: sizes, every path with its geometry, its paint
// servers (pattern tiles dumped inside, indented), and the stream, one
// element a line. Parser tests compare dumps with expected text.
std::string dump(const Scene& scene);

// Does the scene, or a pattern tile or filter source in it, have an
// aliased path (ScenePath::aliased)?
bool has_aliased_paths(const Scene& scene);

}  // namespace mpvg
