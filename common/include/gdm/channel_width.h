// The width of the free room a refined vertex stands in or looks into, and
// the face size that follows it (issue 14, beyond the paper: the paper's
// level of detail, section 6 and Table 2, is one face size for the whole
// model). Local refinement into a channel (DeformOptions::refine_channels)
// makes faces small enough to enter the channel's mouth; the vertices the
// model then makes inside take a face size from the channel's own width, so
// that a sheet of the object a few voxels thick, or a wide room behind a
// narrow mouth, is lined with faces as large as it allows, not with the
// mouth's.
#pragma once

#include "gdm/cost_terms.h"
#include "gdm/volume.h"

namespace gdm {

struct ChannelWidthOptions {
  double voxel = 1.0;     // mm, the sampling step unit
  double cap = 5.0;       // mm, widths are measured up to this (wider: the level of detail fits)
  double edge_per_width = 0.5;  // face edge for a room of width w: this times w (a face a voxel
                                // across enters a channel two voxels wide; 0.6 left 3.7 voxels of
                                // the tooth's pulp canals unfollowed)
};

// The narrowest free chord through p over 13 directions (the axes, the face
// and the body diagonals), each side run until the image blocks, at most
// cap / 2; 0 where p itself is blocked. In a slab it is the slab's
// thickness wherever p lies; in a round channel at most its diameter.
double narrowest_chord(const ImageEvent& image, const Vec3& p, const ChannelWidthOptions& o);

// The width of the room a vertex at p with outward direction `ahead` (unit,
// the sense of deformation) belongs to: when the image is free a voxel
// ahead, the room it looks into; when it is blocked (the vertex stands on a
// wall), the room behind it. The largest narrowest chord along that ray,
// from half a voxel to cap / 2: the chords near the room's middle.
double room_width(const ImageEvent& image, const Vec3& p, const Vec3& ahead, const ChannelWidthOptions& o);

// Whether the free room at `start` reaches `depth` (mm) ahead of the plane
// through `start` normal to `ahead` (unit): a walk over the free points of a
// lattice half a grid spacing apart, 26-connected, kept ahead of the plane
// (behind it lies the model's own inside). A channel or a sheet reaches any
// depth; a noise speck or the hollow of a rough wall does not. The walk
// stops after max_points points (then the room counts as deep: a wide room).
bool free_room_reaches(const ImageEvent& image, const Vec3& start, const Vec3& ahead, double depth,
                       const Vec3& spacing, std::size_t max_points = 4000);

// The face area (mm^2) that follows a room of width w (mm): an equilateral
// face of edge edge_per_width * w, within [finest, coarse].
double area_for_width(double width, const ChannelWidthOptions& o, double finest, double coarse);

}  // namespace gdm
