/*=========================================================================
 *
 *  gdm ITK module: Geometrically Deformed Models as an ITK image-to-mesh filter.
 *
 *=========================================================================*/
#ifndef itkGeometricallyDeformedModelImageToMeshFilter_h
#define itkGeometricallyDeformedModelImageToMeshFilter_h

#include <cstdint>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "itkGDMVolumeConversion.h" // first: loads ITK's Eigen before the gdm headers
#include "itkImageToMeshFilter.h"
#include "itkMacro.h"
#include "itkNumericTraits.h"
#include "itkPoint.h"

#include "gdm/deformer.h"
#include "gdm/option_catalogue.h"

// ITK 5.4 introduced itkOverrideGetNameOfClassMacro; provide it on older ITK.
#ifndef itkOverrideGetNameOfClassMacro
#  define itkOverrideGetNameOfClassMacro(thisClass)                                                                    \
    const char * GetNameOfClass() const override { return #thisClass; }                                               \
    ITK_MACROEND_NOOP_STATEMENT
#endif

namespace itk
{

/** \class GeometricallyDeformedModelEnums
 * \brief Enumerations of GeometricallyDeformedModelImageToMeshFilter.
 * \ingroup GeometricallyDeformedModel
 */
class GeometricallyDeformedModelEnums
{
public:
  /** Grow: the seed starts inside the object and expands (the paper's
   * balloon). Shrink: the seed encloses the object and collapses onto it. */
  enum class Mode : uint8_t
  {
    Grow,
    Shrink
  };

  /** Which side of the threshold is the object. */
  enum class Polarity : uint8_t
  {
    ObjectBrighter,
    ObjectDarker
  };
};

inline std::ostream &
operator<<(std::ostream & os, const GeometricallyDeformedModelEnums::Mode value)
{
  return os << (value == GeometricallyDeformedModelEnums::Mode::Grow ? "GeometricallyDeformedModelEnums::Mode::Grow"
                                                                      : "GeometricallyDeformedModelEnums::Mode::Shrink");
}

inline std::ostream &
operator<<(std::ostream & os, const GeometricallyDeformedModelEnums::Polarity value)
{
  return os << (value == GeometricallyDeformedModelEnums::Polarity::ObjectBrighter
                  ? "GeometricallyDeformedModelEnums::Polarity::ObjectBrighter"
                  : "GeometricallyDeformedModelEnums::Polarity::ObjectDarker");
}

/** \class GeometricallyDeformedModelImageToMeshFilter
 * \brief Extracts a closed triangle mesh of an object in a 3D image with a
 * Geometrically Deformed Model (GDM).
 *
 * A simple closed polyhedron (the seed) is deformed, vertex by vertex, by an
 * adaptive steepest descent on the cost C = a0 D + a1 I + a2 T: a deformation
 * potential D that pushes every vertex along its normal, an image event I that
 * stops it at the threshold, and a topology term T that keeps the surface
 * locally smooth. Faces larger than the level of detail are split while the
 * model deforms, and after convergence the model is refined 1-to-4 and
 * deformed again. The result is a closed, 2-manifold triangle mesh of the
 * seed's genus (0 for the built-in seed) without self-intersections.
 *
 * The work is done by the gdm core library (gdm::deform()); this filter
 * converts the input image (with its spacing, origin and direction cosines)
 * into the core's volume, runs the core and converts the result back. Output
 * points are in the input image's physical space. Each output point carries
 * its generation (the deformation cycle that created it) as point data.
 *
 * Inputs: the image (any scalar pixel type, dimension 3) and, optionally, a
 * closed 2-manifold triangle seed mesh (SetSeedMesh(), in physical
 * coordinates). Without a seed mesh, the seed is a geodesic sphere given by
 * SeedCenter (physical point) and SeedRadius (mm); the subdivision level of the
 * sphere is SeedSubdivisionLevel.
 *
 * Parameters (defaults in brackets; lengths in "voxels" are multiples of the
 * smallest spacing):
 * - Threshold [NaN, must be set]: T of eq. 2, the iso-value of the boundary.
 * - Polarity [ObjectBrighter]: which side of the threshold is the object.
 * - Mode [Grow]: grow from inside the object, or shrink from around it.
 * - DeformationWeight a0 [1], ImageEventWeight a1 [1], TopologyWeight a2 [5]
 *   (Table 2 of the paper); >= 0.
 * - IntensityScale [0 = 1% of the image's value range]: intensity per unit of I.
 * - Reach [1 voxel, in (0, 10]]: distance of the normal-tracking target.
 * - NormalRings [2, in [1, 4]]: rings of faces averaged into a vertex normal.
 * - LocalFlip [on]: flip the deformation sense of vertices that crossed the
 *   boundary.
 * - MinimumStep [0.25] and MaximumStep [1] voxel (in (0, 10]),
 *   MaximumStepReductions [3, in [0, 16]], GradientStep [0.1 voxel, in (0, 1]]:
 *   the adaptive steepest descent (section 3.2).
 * - LevelOfDetailFaceArea [10 voxel^2, >= 0.5]: faces larger than this are split.
 * - LevelOfDetailTopologyExtent [on]: floor the topology term's extent at the
 *   level of detail.
 * - MaximumTopologyRatio [0.5, > 0; infinity = off]: hard limit on eq. 3's
 *   ratio (against leaks through gaps narrower than the level of detail).
 * - RefinementTravel [0.5, > 0; infinity = off]: after a global refinement a
 *   vertex moves at most this many level-of-detail edge lengths from where
 *   the stage found it.
 * - NumberOfGlobalRefinements [1, in [0, 4]]: 1-to-4 resamplings after convergence.
 * - MaximumNumberOfCycles [2000, >= 1], ConvergenceTolerance [0.5 voxel],
 *   ConvergenceWindow [5 cycles]: when to stop.
 * - PreventSelfIntersection [on]: veto moves that would self-intersect.
 * - ImproveTriangles [on] and FlipMaximumDihedralAngle [20 degrees, in [0, 90)]:
 *   Delaunay edge flips on nearly flat regions.
 * - MaximumNumberOfFaces [2000000, >= 20]: stop when the model grows past this.
 * - SubvoxelFit [on]: after the last convergence, move every vertex along its
 *   normal onto the threshold crossing of the trilinear field (beyond the
 *   paper; removes the quarter-voxel shortfall and the curvature term's
 *   inward bias). NumberOfFitPasses [8, in [1, 20]] least-squares sweeps;
 *   FitMaximumDistance [1 voxel, in (0, 4]] bounds each vertex's move;
 *   FitSmoothing [0.5, in [0, 5], 0 = off] draws a vertex toward the quadric
 *   over its 2-ring where it stands within that many image-noise levels of
 *   it (smooths noise, keeps edges and corners).
 * - CurvatureCorrection [on]: the fit's crossings corrected for the trilinear
 *   interpolation's bias on curved surfaces, with the model's curvature where
 *   its 3-ring is a quadric; quiet images only.
 * - SharpEdges [on]: after the fit, vertices onto the object's sharp edges and
 *   corners (where the faces around a vertex lie in two or three flat planes
 *   the data bends between within 1.5 voxels; edges crossing such a line are
 *   split on it). Smooth bends and noisy data are left as they are.
 * - LevelOfDetailTolerance [0 = off, in [0.01, 10] voxels]: error-driven level
 *   of detail after the fit: faces deviating from the threshold surface by
 *   more than this are split, edges whose collapse keeps the new faces within
 *   half of it are collapsed (closed, 2-manifold, genus 0 and
 *   self-intersection free kept). LevelOfDetailMinimumAngle [15 degrees, in
 *   [0, 60)] is the triangle-quality floor of collapses,
 *   LevelOfDetailRounds [6, in [1, 50]] the collapse/split/fit rounds.
 * - MinimumAngle [10 degrees, in [0, 30], 0 = off]: triangle quality, the last
 *   geometric step: every face with a smaller angle is improved by guarded
 *   edge flips, cap splits, short-edge collapses and tangential relaxation on
 *   the model's surface (best effort; guarantees kept).
 * - FaceBudget [0 = off, or in [20, 1e9] and at most MaximumNumberOfFaces]:
 *   the final mesh gets about this many faces (within 5 %): the model is
 *   fitted at a level of detail with more faces (1-to-4 subdivisions and fits
 *   when it has fewer), reduced by guarded edge collapses in order of the
 *   quadric error of the fitted surface and fitted again (guarantees kept);
 *   excludes LevelOfDetailTolerance.
 * - FloatExactOutput [on]: end with every vertex on a float-representable
 *   point, each move checked by the self-intersection guard, so that an
 *   itk::Mesh<float> (or a float file format) keeps the no-self-intersection
 *   guarantee.
 * - NumberOfWorkUnits (from ProcessObject): worker threads; the result does not
 *   depend on it.
 *
 * The numeric parameters of the beyond-the-paper stages (fit, error-driven
 * level of detail, topology ratio, refinement travel) are not clamped by the
 * setters: the core checks them and Update() throws with its message.
 *
 * After Update(), GetStopReason(), GetNumberOfCycles(),
 * GetNumberOfGlobalRefinementsPerformed(), GetNumberOfRejectedMoves(),
 * GetNumberOfFlips(), GetNumberOfBorderVertices(), GetNumberOfFitMoves(),
 * GetNumberOfLevelOfDetailSplits(), GetNumberOfLevelOfDetailCollapses(),
 * GetNumberOfBudgetCollapses() and GetNumberOfFloatRefusedVertices()
 * describe the run.
 *
 * Progress is reported once per deformation cycle and ends at 1. During a
 * ProgressEvent, GetCurrentCycle(), GetCurrentStage(),
 * GetCurrentNumberOfVertices(), GetCurrentNumberOfFaces(),
 * GetCurrentNumberOfMovingVertices(), GetCurrentNumberOfActiveVertices(),
 * GetCurrentNumberOfSplits() and GetCurrentMeanCost() give the figures of the
 * cycle just done (the core's CycleReport; all 0 before the first cycle of a
 * run; after the run, those of its last cycle, before the final fit). Setting
 * AbortGenerateData (e.g. from a progress observer) stops the run at the end
 * of the current cycle and throws itk::ProcessAborted. Invalid input (no
 * threshold, a threshold outside the value range, a seed outside the image or
 * outside the object, ...) throws itk::ExceptionObject with the core's
 * message.
 *
 * Reference: J. V. Miller, D. E. Breen, W. E. Lorensen, R. M. O'Bara and
 * M. J. Wozny, "Geometrically Deformed Models: A Method for Extracting Closed
 * Geometric Models from Volume Data", Computer Graphics (SIGGRAPH '91
 * Proceedings) 25(4):217-226, 1991.
 *
 * \ingroup GeometricallyDeformedModel
 */
template <typename TInputImage, typename TOutputMesh>
class ITK_TEMPLATE_EXPORT GeometricallyDeformedModelImageToMeshFilter
  : public ImageToMeshFilter<TInputImage, TOutputMesh>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(GeometricallyDeformedModelImageToMeshFilter);

  /** Standard class type aliases. */
  using Self = GeometricallyDeformedModelImageToMeshFilter;
  using Superclass = ImageToMeshFilter<TInputImage, TOutputMesh>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  /** Method for creation through the object factory. */
  itkNewMacro(Self);

  /** Run-time type information. */
  itkOverrideGetNameOfClassMacro(GeometricallyDeformedModelImageToMeshFilter);

  using InputImageType = TInputImage;
  using InputImagePixelType = typename InputImageType::PixelType;
  static constexpr unsigned int InputImageDimension = InputImageType::ImageDimension;

  using OutputMeshType = TOutputMesh;
  using OutputMeshPointer = typename OutputMeshType::Pointer;
  static constexpr unsigned int PointDimension = OutputMeshType::PointDimension;
  static_assert(PointDimension == 3, "GeometricallyDeformedModelImageToMeshFilter needs a 3D output mesh");

  /** The optional seed mesh has the type of the output mesh. */
  using SeedMeshType = TOutputMesh;

  /** A physical point (the seed centre). */
  using PointType = Point<double, 3>;

  using ModeEnum = GeometricallyDeformedModelEnums::Mode;
  using PolarityEnum = GeometricallyDeformedModelEnums::Polarity;

  /** Optional seed mesh (closed 2-manifold triangles, physical coordinates).
   * When set, SeedCenter and SeedRadius are ignored. */
  itkSetInputMacro(SeedMesh, SeedMeshType);
  itkGetInputMacro(SeedMesh, SeedMeshType);

  /** Threshold T (eq. 2); must be set and lie inside the image's value range. */
  itkSetMacro(Threshold, double);
  itkGetConstMacro(Threshold, double);

  /** Which side of the threshold is the object. */
  itkSetEnumMacro(Polarity, PolarityEnum);
  itkGetEnumMacro(Polarity, PolarityEnum);

  /** Grow from inside the object or shrink from around it. */
  itkSetEnumMacro(Mode, ModeEnum);
  itkGetEnumMacro(Mode, ModeEnum);

  /** Deformation gain a0 (>= 0; the core rejects 0). */
  itkSetClampMacro(DeformationWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(DeformationWeight, double);

  /** Image event gain a1 (>= 0). */
  itkSetClampMacro(ImageEventWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(ImageEventWeight, double);

  /** Topology gain a2 (>= 0). */
  itkSetClampMacro(TopologyWeight, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(TopologyWeight, double);

  /** Intensity per unit of the image event; 0 selects 1% of the value range. */
  itkSetClampMacro(IntensityScale, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(IntensityScale, double);

  /** Distance of the normal-tracking target, voxels, in [0.01, 10]. */
  itkSetClampMacro(Reach, double, 0.01, 10.0);
  itkGetConstMacro(Reach, double);

  /** Rings of faces averaged into a vertex normal, in [1, 4]. */
  itkSetClampMacro(NormalRings, unsigned int, 1, 4);
  itkGetConstMacro(NormalRings, unsigned int);

  /** Flip the deformation sense of misplaced vertices (section 5). */
  itkSetMacro(LocalFlip, bool);
  itkGetConstMacro(LocalFlip, bool);
  itkBooleanMacro(LocalFlip);

  /** Smallest optimizer step, voxels, in [0.01, 10]; must not exceed MaximumStep. */
  itkSetClampMacro(MinimumStep, double, 0.01, 10.0);
  itkGetConstMacro(MinimumStep, double);

  /** Largest optimizer step, voxels, in [0.01, 10]. */
  itkSetClampMacro(MaximumStep, double, 0.01, 10.0);
  itkGetConstMacro(MaximumStep, double);

  /** Step halvings tried before a vertex stays put, in [0, 16]. */
  itkSetClampMacro(MaximumStepReductions, unsigned int, 0, 16);
  itkGetConstMacro(MaximumStepReductions, unsigned int);

  /** Half width of the central-difference gradient, voxels, in [0.01, 1]. */
  itkSetClampMacro(GradientStep, double, 0.01, 1.0);
  itkGetConstMacro(GradientStep, double);

  /** Faces larger than this area (voxel^2, >= 0.5) are split. */
  itkSetClampMacro(LevelOfDetailFaceArea, double, 0.5, NumericTraits<double>::max());
  itkGetConstMacro(LevelOfDetailFaceArea, double);

  /** Floor the topology term's extent at the level of detail. */
  itkSetMacro(LevelOfDetailTopologyExtent, bool);
  itkGetConstMacro(LevelOfDetailTopologyExtent, bool);
  itkBooleanMacro(LevelOfDetailTopologyExtent);

  /** Global 1-to-4 resamplings, each after a convergence, in [0, 4]. */
  itkSetClampMacro(NumberOfGlobalRefinements, unsigned int, 0, 4);
  itkGetConstMacro(NumberOfGlobalRefinements, unsigned int);

  /** Hard limit on deformation cycles, all stages together (>= 1). */
  itkSetClampMacro(MaximumNumberOfCycles, unsigned int, 1, static_cast<unsigned int>(std::numeric_limits<int>::max()));
  itkGetConstMacro(MaximumNumberOfCycles, unsigned int);

  /** A vertex counts as moving beyond this distance, voxels (>= 0.001). */
  itkSetClampMacro(ConvergenceTolerance, double, 0.001, NumericTraits<double>::max());
  itkGetConstMacro(ConvergenceTolerance, double);

  /** Converged when nothing moved for this many cycles (>= 1). */
  itkSetClampMacro(ConvergenceWindow, unsigned int, 1, static_cast<unsigned int>(std::numeric_limits<int>::max()));
  itkGetConstMacro(ConvergenceWindow, unsigned int);

  /** Veto moves and flips that would make the surface self-intersect. */
  itkSetMacro(PreventSelfIntersection, bool);
  itkGetConstMacro(PreventSelfIntersection, bool);
  itkBooleanMacro(PreventSelfIntersection);

  /** Delaunay edge flips on nearly flat regions. */
  itkSetMacro(ImproveTriangles, bool);
  itkGetConstMacro(ImproveTriangles, bool);
  itkBooleanMacro(ImproveTriangles);

  /** Hard limit on eq. 3's ratio against leaks (> 0; infinity turns it off). */
  itkSetMacro(MaximumTopologyRatio, double);
  itkGetConstMacro(MaximumTopologyRatio, double);

  /** After a global refinement a vertex moves at most this many level-of-detail
   * edge lengths from where the stage found it (> 0; infinity turns it off). */
  itkSetMacro(RefinementTravel, double);
  itkGetConstMacro(RefinementTravel, double);

  /** Gap size G, physical units: the model passes only where a ball of
   * diameter G fits, so openings in the object's wall narrower than G are
   * bridged (capped) and channels wider than G are followed; 0 (or up to two
   * voxels) = no gate. */
  itkSetMacro(GapSize, double);
  itkGetConstMacro(GapSize, double);

  /** Multi-resolution growth, levels in [0, 4] (0 = off, the default): the
   * model first grows in the image reduced 2x per level (a coarse voxel
   * belongs to the object only where its whole block does), coarsest first,
   * each level's model subdivided 1-to-4 as the seed of the next finer one;
   * at full resolution the vertices travel the last voxel or two. Growing
   * only; a level needs 16 voxels per axis. */
  itkSetClampMacro(NumberOfCoarseLevels, unsigned int, 0, 4);
  itkGetConstMacro(NumberOfCoarseLevels, unsigned int);

  /** Growing, start from the surface of the object's voxels instead of
   * growing from the seed (off by default): the voxels are taken from the
   * seed's deepest one as a well-composed topological ball, its surface is
   * reduced to the level of detail's faces, and the model's vertices travel
   * the last voxel. No seams where a grown front would meet itself in a thin
   * shell (a scalp); the seed only says where the object is. */
  itkSetMacro(VoxelSeed, bool);
  itkGetConstMacro(VoxelSeed, bool);
  itkBooleanMacro(VoxelSeed);

  /** Once the last stage converged, refine locally where faces are too large
   * to enter a channel the image shows, so channels wider than the gap are
   * followed at any level of detail (a tooth's canals). On by default; off,
   * the face size decides where the model goes, as in the paper. */
  itkSetMacro(RefineChannels, bool);
  itkGetConstMacro(RefineChannels, bool);
  itkBooleanMacro(RefineChannels);

  /** Growing, fill the background the outside cannot reach (a hollow
   * shell's inside; chambers joined to the outside only through openings
   * narrower than the cavity opening, SetOption("cavity_opening", W), three
   * voxels by default) and cap each handle by a membrane across its hole
   * (SetOption("cap_handles", 0) to keep the handle) before the model grows:
   * the model is the object's outer surface, without a double-walled sheet
   * around each cavity. On by default. */
  itkSetMacro(FillCavities, bool);
  itkGetConstMacro(FillCavities, bool);
  itkBooleanMacro(FillCavities);

  /** The model's topology, growing: "solid" (default: one closed genus-0
   * outer surface, cavities filled, handles capped) or "exact" (the data's
   * topology: each enclosed cavity also its own closed component with normals
   * into the cavity, each handle a tube through its hole; needs
   * FillCavities). Throws
   * itk::ExceptionObject for another name. */
  void
  SetTopology(const std::string & topology)
  {
    this->SetChoice("topology", topology);
  }
  std::string
  GetTopology() const
  {
    return this->GetChoice("topology");
  }

  /** How each handle is removed (with FillCavities and
   * SetOption("cap_handles", 1), growing, topology "solid"): "membrane"
   * (default: background across the hole given to the object where the hole
   * is narrowest; the model closes the hole) or "cut" (object across the
   * handle's body given to the background where the body is thinnest; the
   * model follows the hole and parts at the cut). GetNumberOfCappedHandles()
   * counts the handles either way. Throws itk::ExceptionObject for another
   * name. */
  void
  SetHandleRepair(const std::string & repair)
  {
    this->SetChoice("handle_repair", repair);
  }
  std::string
  GetHandleRepair() const
  {
    return this->GetChoice("handle_repair");
  }

  /** Sub-voxel final fit onto the threshold crossing (beyond the paper). */
  itkSetMacro(SubvoxelFit, bool);
  itkGetConstMacro(SubvoxelFit, bool);
  itkBooleanMacro(SubvoxelFit);

  /** The fit's crossings corrected for the trilinear field's bias on curved surfaces (quiet images). */
  itkSetMacro(CurvatureCorrection, bool);
  itkGetConstMacro(CurvatureCorrection, bool);
  itkBooleanMacro(CurvatureCorrection);

  /** Vertices onto the object's sharp edges and corners after the fit. */
  itkSetMacro(SharpEdges, bool);
  itkGetConstMacro(SharpEdges, bool);
  itkBooleanMacro(SharpEdges);

  /** Least-squares sweeps of the sub-voxel fit, in [1, 20]. */
  itkSetMacro(NumberOfFitPasses, unsigned int);
  itkGetConstMacro(NumberOfFitPasses, unsigned int);

  /** A vertex moves at most this far in the fit, voxels, in (0, 4]. */
  itkSetMacro(FitMaximumDistance, double);
  itkGetConstMacro(FitMaximumDistance, double);
  itkSetMacro(FitSmoothing, double);
  itkGetConstMacro(FitSmoothing, double);

  /** Error-driven level of detail: largest deviation of a face from the
   * threshold surface, voxels (smallest spacing), in [0.01, 10]; 0 = off. */
  itkSetMacro(LevelOfDetailTolerance, double);
  itkGetConstMacro(LevelOfDetailTolerance, double);

  /** Smallest angle a collapse may create (or the smallest already there), degrees, in [0, 60). */
  itkSetMacro(LevelOfDetailMinimumAngle, double);
  itkGetConstMacro(LevelOfDetailMinimumAngle, double);

  /** Collapse / split / fit rounds of the error-driven level of detail, in [1, 50]. */
  itkSetMacro(LevelOfDetailRounds, unsigned int);
  itkGetConstMacro(LevelOfDetailRounds, unsigned int);

  /** Triangle quality: faces with an angle below this are improved as the
   * last geometric step (best effort), degrees, in [0, 30]; 0 = off. */
  itkSetMacro(MinimumAngle, double);
  itkGetConstMacro(MinimumAngle, double);

  /** Face budget: the final mesh gets about this many faces (within 5 %);
   * 0 = off (the level of detail decides), else in [20, 1e9] and at most
   * MaximumNumberOfFaces; not with LevelOfDetailTolerance. */
  itkSetMacro(FaceBudget, SizeValueType);
  itkGetConstMacro(FaceBudget, SizeValueType);

  /** End with every vertex on a float-representable point, each move checked
   * by the self-intersection guard (float meshes keep the guarantee). */
  itkSetMacro(FloatExactOutput, bool);
  itkGetConstMacro(FloatExactOutput, bool);
  itkBooleanMacro(FloatExactOutput);

  /** Only flip where the faces are this close to flat, degrees, in [0, 89.9]. */
  itkSetClampMacro(FlipMaximumDihedralAngle, double, 0.0, 89.9);
  itkGetConstMacro(FlipMaximumDihedralAngle, double);

  /** Stop when the model grows past this many faces (>= 20). */
  itkSetClampMacro(MaximumNumberOfFaces, SizeValueType, 20, NumericTraits<SizeValueType>::max());
  itkGetConstMacro(MaximumNumberOfFaces, SizeValueType);

  /** Centre of the built-in seed sphere, physical coordinates. */
  itkSetMacro(SeedCenter, PointType);
  itkGetConstReferenceMacro(SeedCenter, PointType);

  /** Radius of the built-in seed sphere, physical units (> 0 to be used). */
  itkSetClampMacro(SeedRadius, double, 0.0, NumericTraits<double>::max());
  itkGetConstMacro(SeedRadius, double);

  /** Subdivisions of the icosahedron seed (20 * 4^level faces), in [0, 4] (level 5 faces are already below any level of detail). */
  itkSetClampMacro(SeedSubdivisionLevel, unsigned int, 0, 4);
  itkGetConstMacro(SeedSubdivisionLevel, unsigned int);

  /** Results of the last run. */
  itkGetStringMacro(StopReason);
  itkGetConstMacro(NumberOfCycles, SizeValueType);
  itkGetConstMacro(NumberOfGlobalRefinementsPerformed, SizeValueType);
  itkGetConstMacro(NumberOfRejectedMoves, SizeValueType);
  itkGetConstMacro(NumberOfFlips, SizeValueType);
  itkGetConstMacro(NumberOfBorderVertices, SizeValueType);
  /** Vertex moves of the sub-voxel fit (also those of the error-driven level of detail). */
  itkGetConstMacro(NumberOfFitMoves, SizeValueType);
  /** Edges split and collapsed by the error-driven level of detail. */
  itkGetConstMacro(NumberOfLevelOfDetailSplits, SizeValueType);
  itkGetConstMacro(NumberOfLevelOfDetailCollapses, SizeValueType);
  /** Vertices FloatExactOutput could not move safely onto a float point (0 in practice). */
  itkGetConstMacro(NumberOfFloatRefusedVertices, SizeValueType);
  /** Edges collapsed to meet the face budget (0 when it is off). */
  itkGetConstMacro(NumberOfBudgetCollapses, SizeValueType);
  /** Free voxels the gap closed (beyond openings or channels narrower than
   * GapSize; 0 without a gate) and vertices of the caps over bridged openings. */
  itkGetConstMacro(NumberOfGapClosedVoxels, SizeValueType);
  itkGetConstMacro(NumberOfBridgeVertices, SizeValueType);
  /** Enclosed regions of background FillCavities filled, and their volume
   * (physical units^3). */
  itkGetConstMacro(NumberOfFilledCavities, SizeValueType);
  itkGetConstMacro(FilledCavityVolume, double);
  /** Of those, the pockets joined to the outside only through openings
   * narrower than the cavity opening; and the handles capped by a membrane
   * across the hole at its narrowest place (the model stays genus 0). */
  itkGetConstMacro(NumberOfCavitiesBehindNarrowOpenings, SizeValueType);
  itkGetConstMacro(NumberOfCappedHandles, SizeValueType);
  /** With the exact topology, the enclosed cavities added as closed inward
   * components; the output's genus and components (checked against its Euler
   * characteristic). */
  itkGetConstMacro(NumberOfCavityComponents, SizeValueType);
  itkGetConstMacro(Genus, SizeValueType);
  itkGetConstMacro(NumberOfComponents, SizeValueType);
  /** Where the model meets itself (two parts of the surface closer than a
   * voxel, facing each other): regions and their area (physical units^2).
   * A region across the object means the model grew around a cavity or a
   * handle from two sides and the surface there is not the object's:
   * SeamArea is the area of those regions, the part of ContactArea that is
   * a defect (the rest: slits of background thinner than a voxel). */
  itkGetConstMacro(NumberOfContactRegions, SizeValueType);
  itkGetConstMacro(ContactArea, double);
  itkGetConstMacro(SeamArea, double);

  /** The cycle just done, readable during a ProgressEvent (the core's
   * CycleReport). Cycle is 1-based, 0 before the first cycle of a run; Stage
   * counts the global refinements done so far. */
  itkGetConstMacro(CurrentCycle, SizeValueType);
  itkGetConstMacro(CurrentStage, SizeValueType);
  /** Size of the model after the cycle. */
  itkGetConstMacro(CurrentNumberOfVertices, SizeValueType);
  itkGetConstMacro(CurrentNumberOfFaces, SizeValueType);
  /** Vertices that moved in the cycle (the run converges when none moves
   * beyond ConvergenceTolerance for ConvergenceWindow cycles). */
  itkGetConstMacro(CurrentNumberOfMovingVertices, SizeValueType);
  /** Vertices whose cost the cycle evaluated (the active set). */
  itkGetConstMacro(CurrentNumberOfActiveVertices, SizeValueType);
  /** Edges split by the cycle's local resampling (level of detail). */
  itkGetConstMacro(CurrentNumberOfSplits, SizeValueType);
  /** Mean vertex cost after the cycle. */
  itkGetConstMacro(CurrentMeanCost, double);

  /** The core options assembled from the parameters above. */
  gdm::DeformOptions
  GetDeformOptions() const;

  /** Sets every parameter above from the core's options (the constructor
   * starts from gdm::DeformOptions{}, the core's defaults). */
  void
  SetDeformOptions(const gdm::DeformOptions & options);

  /** Any option of the core's catalogue by its name (docs/options.md), e.g.
   * SetOption("lod_tolerance", 0.1): also the options without a Set/Get of
   * their own. Throws itk::ExceptionObject for an unknown name or a value out
   * of the catalogue's range (booleans are 0/1, choices their index). */
  void
  SetOption(const std::string & name, double value);
  double
  GetOption(const std::string & name) const;

protected:
  /** The names of a choice option, by value (the catalogue's). */
  static const std::vector<std::string> &
  ChoiceNames(const std::string & name)
  {
    for (const auto & option : gdm::deform_option_catalogue())
    {
      if (option.name == name)
      {
        return option.choices;
      }
    }
    static const std::vector<std::string> none;
    return none;
  }

  /** A choice option set by one of its names; throws for another name. */
  void
  SetChoice(const std::string & name, const std::string & value)
  {
    const auto & names = ChoiceNames(name);
    for (std::size_t i = 0; i < names.size(); ++i)
    {
      if (names[i] == value)
      {
        this->SetOption(name, static_cast<double>(i));
        return;
      }
    }
    std::string known;
    for (const auto & n : names)
    {
      known += (known.empty() ? "" : " or ") + n;
    }
    itkExceptionMacro(<< name << " must be " << known << ", got " << value);
  }
  std::string
  GetChoice(const std::string & name) const
  {
    return ChoiceNames(name).at(static_cast<std::size_t>(this->GetOption(name)));
  }

  GeometricallyDeformedModelImageToMeshFilter();
  ~GeometricallyDeformedModelImageToMeshFilter() override = default;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

  void
  GenerateData() override;

private:
  /** Copies one cycle's report into the Current* members. */
  void
  SetCurrentCycleReport(const gdm::CycleReport & report);

  double        m_Threshold;
  PolarityEnum  m_Polarity{ PolarityEnum::ObjectBrighter };
  ModeEnum      m_Mode{ ModeEnum::Grow };
  double        m_DeformationWeight;
  double        m_ImageEventWeight;
  double        m_TopologyWeight;
  double        m_IntensityScale;
  double        m_Reach;
  unsigned int  m_NormalRings;
  bool          m_LocalFlip;
  double        m_MinimumStep;
  double        m_MaximumStep;
  unsigned int  m_MaximumStepReductions;
  double        m_GradientStep;
  double        m_LevelOfDetailFaceArea;
  bool          m_LevelOfDetailTopologyExtent;
  unsigned int  m_NumberOfGlobalRefinements;
  unsigned int  m_MaximumNumberOfCycles;
  double        m_ConvergenceTolerance;
  unsigned int  m_ConvergenceWindow;
  bool          m_PreventSelfIntersection;
  bool          m_ImproveTriangles;
  double        m_FlipMaximumDihedralAngle;
  SizeValueType m_MaximumNumberOfFaces;
  double        m_MaximumTopologyRatio;
  double        m_RefinementTravel;
  double        m_GapSize;
  bool          m_RefineChannels;
  unsigned int  m_NumberOfCoarseLevels;
  bool          m_VoxelSeed;
  bool          m_FillCavities;
  bool          m_SubvoxelFit;
  bool          m_CurvatureCorrection;
  bool          m_SharpEdges;
  unsigned int  m_NumberOfFitPasses;
  double        m_FitMaximumDistance;
  double        m_FitSmoothing;
  double        m_LevelOfDetailTolerance;
  double        m_LevelOfDetailMinimumAngle;
  unsigned int  m_LevelOfDetailRounds;
  double        m_MinimumAngle;
  SizeValueType m_FaceBudget;
  bool          m_FloatExactOutput;
  /** The core options not held in the members above (reached by SetOption). */
  gdm::DeformOptions m_CatalogueOptions;
  PointType     m_SeedCenter;
  double        m_SeedRadius{ 0.0 };
  unsigned int  m_SeedSubdivisionLevel{ 1 };

  std::string   m_StopReason;
  SizeValueType m_NumberOfCycles{ 0 };
  SizeValueType m_NumberOfGlobalRefinementsPerformed{ 0 };
  SizeValueType m_NumberOfRejectedMoves{ 0 };
  SizeValueType m_NumberOfFlips{ 0 };
  SizeValueType m_NumberOfBorderVertices{ 0 };
  SizeValueType m_NumberOfFitMoves{ 0 };
  SizeValueType m_NumberOfLevelOfDetailSplits{ 0 };
  SizeValueType m_NumberOfLevelOfDetailCollapses{ 0 };
  SizeValueType m_NumberOfFloatRefusedVertices{ 0 };
  SizeValueType m_NumberOfBudgetCollapses{ 0 };
  SizeValueType m_NumberOfGapClosedVoxels{ 0 };
  SizeValueType m_NumberOfBridgeVertices{ 0 };
  SizeValueType m_NumberOfFilledCavities{ 0 };
  double        m_FilledCavityVolume{ 0.0 };
  SizeValueType m_NumberOfCavitiesBehindNarrowOpenings{ 0 };
  SizeValueType m_NumberOfCappedHandles{ 0 };
  SizeValueType m_NumberOfCavityComponents{ 0 };
  SizeValueType m_Genus{ 0 };
  SizeValueType m_NumberOfComponents{ 0 };
  SizeValueType m_NumberOfContactRegions{ 0 };
  double        m_ContactArea{ 0.0 };
  double        m_SeamArea{ 0.0 };

  SizeValueType m_CurrentCycle{ 0 };
  SizeValueType m_CurrentStage{ 0 };
  SizeValueType m_CurrentNumberOfVertices{ 0 };
  SizeValueType m_CurrentNumberOfFaces{ 0 };
  SizeValueType m_CurrentNumberOfMovingVertices{ 0 };
  SizeValueType m_CurrentNumberOfActiveVertices{ 0 };
  SizeValueType m_CurrentNumberOfSplits{ 0 };
  double        m_CurrentMeanCost{ 0.0 };
};
} // end namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkGeometricallyDeformedModelImageToMeshFilter.hxx"
#endif

#endif // itkGeometricallyDeformedModelImageToMeshFilter_h
