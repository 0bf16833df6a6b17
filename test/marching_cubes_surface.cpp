#include "marching_cubes_surface.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace gdm::test {

std::vector<Triangle> marching_cubes(const Volume& volume, double threshold) {
  static const int edge_corner[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                         {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  static const int face_corner[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                        {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
  int edge_of[8][8];
  for (int e = 0; e < 12; ++e) {
    edge_of[edge_corner[e][0]][edge_corner[e][1]] = e;
    edge_of[edge_corner[e][1]][edge_corner[e][0]] = e;
  }
  std::vector<Triangle> out;
  const auto& d = volume.dims();
  for (int z = 0; z + 1 < d[2]; ++z)
    for (int y = 0; y + 1 < d[1]; ++y)
      for (int x = 0; x + 1 < d[0]; ++x) {
        double value[8];
        bool in[8];
        int count = 0;
        for (int c = 0; c < 8; ++c) {
          value[c] = volume.at(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
          in[c] = value[c] >= threshold;
          count += in[c];
        }
        if (count == 0 || count == 8) continue;
        // Segments on the cube faces join crossed edges; each crossed edge
        // has two neighbours, and the loops are the cell's polygons.
        int nb[12][2], deg[12] = {0};
        const auto join = [&](int a, int b) {
          nb[a][deg[a]++] = b;
          nb[b][deg[b]++] = a;
        };
        for (const auto& f : face_corner) {
          int es[4], n = 0;
          for (int k = 0; k < 4; ++k) {
            const int e = edge_of[f[k]][f[(k + 1) % 4]];
            if (in[edge_corner[e][0]] != in[edge_corner[e][1]]) es[n++] = e;
          }
          if (n == 2) {
            join(es[0], es[1]);
          } else if (n == 4) {
            for (int k = 0; k < 4; ++k)
              if (in[f[k]]) join(edge_of[f[(k + 3) % 4]][f[k]], edge_of[f[k]][f[(k + 1) % 4]]);
          }
        }
        Vec3 point[12];
        for (int e = 0; e < 12; ++e) {
          if (deg[e] == 0) continue;
          const int a = edge_corner[e][0], b = edge_corner[e][1];
          const double t = (threshold - value[a]) / (value[b] - value[a]);
          const Vec3 ia(x + (a & 1), y + ((a >> 1) & 1), z + ((a >> 2) & 1));
          const Vec3 ib(x + (b & 1), y + ((b >> 1) & 1), z + ((b >> 2) & 1));
          point[e] = volume.to_physical(ia + t * (ib - ia));
        }
        bool used[12] = {false};
        for (int start = 0; start < 12; ++start) {
          if (deg[start] != 2 || used[start]) continue;
          std::vector<int> loop{start};
          used[start] = true;
          int prev = -1, cur = start;
          while (true) {
            const int next = nb[cur][0] != prev ? nb[cur][0] : nb[cur][1];
            if (next == start || used[next]) break;
            loop.push_back(next);
            used[next] = true;
            prev = cur;
            cur = next;
          }
          for (std::size_t k = 1; k + 1 < loop.size(); ++k)
            out.push_back({point[loop[0]], point[loop[k]], point[loop[k + 1]]});
        }
      }
  return out;
}

}  // namespace gdm::test
