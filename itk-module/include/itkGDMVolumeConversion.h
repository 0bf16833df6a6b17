/*=========================================================================
 *
 *  gdm ITK module: conversions between ITK images/meshes and the gdm core.
 *
 *=========================================================================*/
#ifndef itkGDMVolumeConversion_h
#define itkGDMVolumeConversion_h

#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

// ITK 5.2 bundles Eigen 3.3 (itkeigen/) with the same include guards as the
// system Eigen 3.4 used by the gdm headers. Whichever comes first wins; ITK's
// Eigenvalues module only compiles against its own Eigen core, while the gdm
// headers compile against either. So ITK's Eigen is loaded here, before any
// gdm header: in a translation unit that mixes ITK and gdm, include this
// header (or any ITK header that uses Eigen, e.g. itkImageIOBase.h) before
// including gdm headers directly.
#include "itkSymmetricEigenAnalysis.h"

#include "itkImage.h"
#include "itkImageRegionConstIterator.h"
#include "itkMesh.h"
#include "itkQuadEdgeMesh.h"
#include "itkTriangleCell.h"

#include "gdm/errors.h"
#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace itk
{
namespace GDMConversion
{

/** True when TMesh is an itk::QuadEdgeMesh (it defines QEPrimal). */
template <typename TMesh, typename = void>
struct IsQuadEdgeMesh : std::false_type
{};
template <typename TMesh>
struct IsQuadEdgeMesh<TMesh, std::void_t<typename TMesh::QEPrimal>> : std::true_type
{};

/** Builds a gdm::Volume from a 3D ITK image, keeping spacing, origin and
 * direction cosines: the volume's physical space is the image's physical
 * space. Only the buffered region is converted; its first voxel becomes the
 * volume's index (0,0,0), so the volume origin is the physical point of that
 * voxel. Pixels are cast to float. Throws gdm::InvalidVolume (through the
 * gdm::Volume constructor) when the grid cannot be used, e.g. an empty
 * image or a dimension below 2. */
template <typename TPixel>
gdm::Volume
VolumeFromImage(const Image<TPixel, 3> * image)
{
  using ImageType = Image<TPixel, 3>;
  if (image == nullptr)
  {
    throw gdm::InvalidVolume("the input image is null");
  }
  const typename ImageType::RegionType region = image->GetBufferedRegion();
  const typename ImageType::SizeType   size = region.GetSize();
  gdm::Index3                          dims;
  for (unsigned int d = 0; d < 3; ++d)
  {
    dims[d] = static_cast<int>(size[d]);
  }

  std::vector<float> values;
  values.reserve(region.GetNumberOfPixels());
  ImageRegionConstIterator<ImageType> it(image, region);
  for (it.GoToBegin(); !it.IsAtEnd(); ++it)
  {
    values.push_back(static_cast<float>(it.Get()));
  }

  gdm::Vec3       spacing;
  gdm::Vec3       origin;
  Eigen::Matrix3d direction;
  typename ImageType::PointType first;
  image->TransformIndexToPhysicalPoint(region.GetIndex(), first);
  for (unsigned int r = 0; r < 3; ++r)
  {
    spacing[r] = image->GetSpacing()[r];
    origin[r] = first[r];
    for (unsigned int c = 0; c < 3; ++c)
    {
      direction(r, c) = image->GetDirection()[r][c];
    }
  }
  return gdm::Volume(dims, std::move(values), spacing, origin, direction);
}

/** Fills `output` (an itk::Mesh or itk::QuadEdgeMesh) with the points and
 * triangles of `input`. Point identifiers are the OpenMesh vertex indices;
 * cell identifiers (itk::Mesh) follow the OpenMesh face order. When the core
 * mesh carries the per-vertex generation ("v:generation"), it is stored as
 * point data (cast to TMesh::PixelType). Any previous content of `output` is
 * discarded. */
template <typename TMesh>
void
MeshToITKMesh(const gdm::Mesh & input, TMesh * output)
{
  using PointType = typename TMesh::PointType;
  using PixelType = typename TMesh::PixelType;
  using PointIdentifier = typename TMesh::PointIdentifier;
  using CellIdentifier = typename TMesh::CellIdentifier;

  if (output == nullptr)
  {
    throw gdm::Error("the output mesh is null");
  }
  output->Initialize();
  output->SetPoints(TMesh::PointsContainer::New());
  output->SetPointData(TMesh::PointDataContainer::New());
  if constexpr (!IsQuadEdgeMesh<TMesh>::value)
  {
    output->SetCells(TMesh::CellsContainer::New());
    output->SetCellData(TMesh::CellDataContainer::New());
  }

  output->GetPoints()->Reserve(input.n_vertices());
  const auto generation = gdm::find_generation_property(input);
  for (auto v : input.vertices())
  {
    const auto & p = input.point(v);
    PointType    q;
    for (unsigned int d = 0; d < 3; ++d)
    {
      q[d] = static_cast<typename PointType::ValueType>(p[d]);
    }
    const auto id = static_cast<PointIdentifier>(v.idx());
    output->SetPoint(id, q);
    const int gen = generation.is_valid() ? input.property(generation, v) : 0;
    output->SetPointData(id, static_cast<PixelType>(gen));
  }

  CellIdentifier cellId = 0;
  for (auto f : input.faces())
  {
    PointIdentifier ids[3];
    int             n = 0;
    for (auto v : input.fv_range(f))
    {
      if (n < 3)
      {
        ids[n] = static_cast<PointIdentifier>(v.idx());
      }
      ++n;
    }
    if (n != 3)
    {
      throw gdm::Error("face " + std::to_string(f.idx()) + " of the mesh is not a triangle");
    }
    if constexpr (IsQuadEdgeMesh<TMesh>::value)
    {
      if (output->AddFaceTriangle(ids[0], ids[1], ids[2]) == nullptr)
      {
        throw gdm::Error("face " + std::to_string(f.idx()) +
                         " could not be added to the QuadEdgeMesh (non-manifold input)");
      }
    }
    else
    {
      using CellAutoPointer = typename TMesh::CellAutoPointer;
      using TriangleType = TriangleCell<typename TMesh::CellType>;
      CellAutoPointer cell;
      cell.TakeOwnership(new TriangleType);
      for (unsigned int k = 0; k < 3; ++k)
      {
        cell->SetPointId(k, ids[k]);
      }
      output->SetCell(cellId, cell);
    }
    ++cellId;
  }
}

/** Builds a gdm::Mesh from the triangles of an itk::Mesh or itk::QuadEdgeMesh
 * (e.g. a seed). Cells that are not triangles (vertices, edges) are ignored;
 * polygons with more than 3 points raise gdm::InvalidSeed. Points that no
 * triangle uses are dropped. No check for closedness is made here: the core's
 * deform() checks the seed. */
template <typename TMesh>
gdm::Mesh
MeshFromITKMesh(const TMesh * input)
{
  using PointIdentifier = typename TMesh::PointIdentifier;
  if (input == nullptr || input->GetPoints() == nullptr)
  {
    throw gdm::InvalidSeed("the seed mesh is null or has no points");
  }
  gdm::Mesh mesh;
  std::unordered_map<PointIdentifier, gdm::Mesh::VertexHandle> handles;
  const auto * points = input->GetPoints();
  handles.reserve(points->Size());
  for (auto it = points->Begin(); it != points->End(); ++it)
  {
    const auto & p = it.Value();
    handles[it.Index()] = mesh.add_vertex(gdm::Mesh::Point(p[0], p[1], p[2]));
  }
  auto lookup = [&](PointIdentifier id) -> gdm::Mesh::VertexHandle {
    const auto found = handles.find(id);
    return found == handles.end() ? gdm::Mesh::VertexHandle() : found->second;
  };

  if (input->GetCells() != nullptr)
  {
    for (auto it = input->GetCells()->Begin(); it != input->GetCells()->End(); ++it)
    {
      const auto * cell = it.Value();
      const auto   n = cell->GetNumberOfPoints();
      if (n < 3)
      {
        continue;
      }
      if (n > 3)
      {
        throw gdm::InvalidSeed("the seed mesh has a cell with " + std::to_string(n) +
                               " points; only triangles are accepted");
      }
      gdm::Mesh::VertexHandle vh[3];
      int                     k = 0;
      for (auto pit = cell->PointIdsBegin(); pit != cell->PointIdsEnd() && k < 3; ++pit, ++k)
      {
        vh[k] = lookup(*pit);
        if (!vh[k].is_valid())
        {
          throw gdm::InvalidSeed("the seed mesh has a cell referring to a missing point");
        }
      }
      if (!mesh.add_face(vh[0], vh[1], vh[2]).is_valid())
      {
        throw gdm::InvalidSeed("the seed mesh is not a 2-manifold (a triangle could not be added)");
      }
    }
  }
  // Drop points that no triangle uses.
  bool isolated = false;
  for (auto v : mesh.vertices())
  {
    if (mesh.is_isolated(v))
    {
      isolated = true;
      break;
    }
  }
  if (isolated)
  {
    mesh.request_vertex_status();
    mesh.request_edge_status();
    mesh.request_face_status();
    for (auto v : mesh.vertices())
    {
      if (mesh.is_isolated(v))
      {
        mesh.delete_vertex(v, false);
      }
    }
    mesh.garbage_collection();
    mesh.release_vertex_status();
    mesh.release_edge_status();
    mesh.release_face_status();
  }
  return mesh;
}

} // namespace GDMConversion
} // namespace itk

#endif // itkGDMVolumeConversion_h
