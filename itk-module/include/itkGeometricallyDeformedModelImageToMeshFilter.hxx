/*=========================================================================
 *
 *  gdm ITK module: Geometrically Deformed Models as an ITK image-to-mesh filter.
 *
 *=========================================================================*/
#ifndef itkGeometricallyDeformedModelImageToMeshFilter_hxx
#define itkGeometricallyDeformedModelImageToMeshFilter_hxx

#include "itkGeometricallyDeformedModelImageToMeshFilter.h"

#include <algorithm>
#include <cmath>
#include <exception>

#include "itkGDMVolumeConversion.h"

#include "gdm/errors.h"
#include "gdm/option_catalogue.h"
#include "gdm/pipeline.h"

namespace itk
{

template <typename TInputImage, typename TOutputMesh>
GeometricallyDeformedModelImageToMeshFilter<TInputImage, TOutputMesh>::GeometricallyDeformedModelImageToMeshFilter()
{
  // The defaults are the core's.
  this->SetDeformOptions(gdm::DeformOptions{});
  m_SeedCenter.Fill(0.0);
}

template <typename TInputImage, typename TOutputMesh>
void
GeometricallyDeformedModelImageToMeshFilter<TInputImage, TOutputMesh>::SetDeformOptions(const gdm::DeformOptions & o)
{
  m_CatalogueOptions = o;
  m_Threshold = o.threshold;
  m_Polarity = o.polarity == gdm::Polarity::object_darker ? PolarityEnum::ObjectDarker
                                                                  : PolarityEnum::ObjectBrighter;
  m_Mode = o.mode == gdm::Mode::shrink ? ModeEnum::Shrink : ModeEnum::Grow;
  m_DeformationWeight = o.a0;
  m_ImageEventWeight = o.a1;
  m_TopologyWeight = o.a2;
  m_IntensityScale = o.intensity_scale;
  m_Reach = o.reach;
  m_NormalRings = static_cast<unsigned int>(o.normal_rings);
  m_LocalFlip = o.local_flip;
  m_MinimumStep = o.optimizer.min_step;
  m_MaximumStep = o.optimizer.max_step;
  m_MaximumStepReductions = static_cast<unsigned int>(o.optimizer.max_step_reductions);
  m_GradientStep = o.optimizer.gradient_step;
  m_LevelOfDetailFaceArea = o.lod_face_area;
  m_LevelOfDetailTopologyExtent = o.lod_topology_extent;
  m_NumberOfGlobalRefinements = static_cast<unsigned int>(o.global_refinements);
  m_MaximumNumberOfCycles = static_cast<unsigned int>(o.max_cycles);
  m_ConvergenceTolerance = o.convergence_tolerance;
  m_ConvergenceWindow = static_cast<unsigned int>(o.convergence_window);
  m_PreventSelfIntersection = o.prevent_self_intersection;
  m_ImproveTriangles = o.improve_triangles;
  m_FlipMaximumDihedralAngle = o.flip_max_dihedral;
  m_MaximumNumberOfFaces = static_cast<SizeValueType>(o.max_faces);
  m_MaximumTopologyRatio = o.max_topology_ratio;
  m_RefinementTravel = o.refinement_travel;
  m_GapSize = o.gap;
  m_RefineChannels = o.refine_channels;
  m_NumberOfCoarseLevels = static_cast<unsigned int>(o.coarse_levels);
  m_VoxelSeed = o.voxel_seed;
  m_FillCavities = o.fill_cavities;
  m_SubvoxelFit = o.subvoxel_fit;
  m_CurvatureCorrection = o.curvature_correction;
  m_SharpEdges = o.sharp_edges;
  m_NumberOfFitPasses = static_cast<unsigned int>(o.fit_passes);
  m_FitMaximumDistance = o.fit_max_distance;
  m_FitSmoothing = o.fit_smoothing;
  m_LevelOfDetailTolerance = o.lod_tolerance;
  m_LevelOfDetailMinimumAngle = o.lod_min_angle;
  m_LevelOfDetailRounds = static_cast<unsigned int>(o.lod_rounds);
  m_MinimumAngle = o.min_angle;
  m_FaceBudget = static_cast<SizeValueType>(o.face_budget);
  m_FloatExactOutput = o.float_exact_output;
  if (o.threads > 0)
  {
    this->SetNumberOfWorkUnits(static_cast<ThreadIdType>(o.threads));
  }
  this->Modified();
}

template <typename TInputImage, typename TOutputMesh>
void
GeometricallyDeformedModelImageToMeshFilter<TInputImage, TOutputMesh>::SetOption(const std::string & name, double value)
{
  for (const auto & option : gdm::deform_option_catalogue())
  {
    if (option.name == name)
    {
      if (!gdm::accepts(option, value))
      {
        itkExceptionMacro(<< name << " must be " << gdm::range_text(option) << ", got " << value);
      }
      gdm::DeformOptions o = this->GetDeformOptions();
      option.set(o, value);
      this->SetDeformOptions(o);
      return;
    }
  }
  itkExceptionMacro(<< "no option " << name << " (see docs/options.md)");
}

template <typename TInputImage, typename TOutputMesh>
double
GeometricallyDeformedModelImageToMeshFilter<TInputImage, TOutputMesh>::GetOption(const std::string & name) const
{
  const gdm::DeformOptions o = this->GetDeformOptions();
  for (const auto & option : gdm::deform_option_catalogue())
  {
    if (option.name == name)
    {
      return option.get(o);
    }
  }
  itkExceptionMacro(<< "no option " << name << " (see docs/options.md)");
}

template <typename TInputImage, typename TOutputMesh>
gdm::DeformOptions
GeometricallyDeformedModelImageToMeshFilter<TInputImage, TOutputMesh>::GetDeformOptions() const
{
  // Options without a Set/Get of their own keep the value SetOption gave them.
  gdm::DeformOptions o = m_CatalogueOptions;
  o.mode = m_Mode == ModeEnum::Shrink ? gdm::Mode::shrink : gdm::Mode::grow;
  o.polarity = m_Polarity == PolarityEnum::ObjectDarker ? gdm::Polarity::object_darker
                                                        : gdm::Polarity::object_brighter;
  o.threshold = m_Threshold;
  o.a0 = m_DeformationWeight;
  o.a1 = m_ImageEventWeight;
  o.a2 = m_TopologyWeight;
  o.intensity_scale = m_IntensityScale;
  o.reach = m_Reach;
  o.normal_rings = static_cast<int>(m_NormalRings);
  o.local_flip = m_LocalFlip;
  o.optimizer.min_step = m_MinimumStep;
  o.optimizer.max_step = m_MaximumStep;
  o.optimizer.max_step_reductions = static_cast<int>(m_MaximumStepReductions);
  o.optimizer.gradient_step = m_GradientStep;
  o.lod_face_area = m_LevelOfDetailFaceArea;
  o.lod_topology_extent = m_LevelOfDetailTopologyExtent;
  o.global_refinements = static_cast<int>(m_NumberOfGlobalRefinements);
  o.max_cycles = static_cast<int>(m_MaximumNumberOfCycles);
  o.convergence_tolerance = m_ConvergenceTolerance;
  o.convergence_window = static_cast<int>(m_ConvergenceWindow);
  o.prevent_self_intersection = m_PreventSelfIntersection;
  o.improve_triangles = m_ImproveTriangles;
  o.flip_max_dihedral = m_FlipMaximumDihedralAngle;
  o.threads = static_cast<int>(this->GetNumberOfWorkUnits());
  o.max_faces = static_cast<std::size_t>(m_MaximumNumberOfFaces);
  o.max_topology_ratio = m_MaximumTopologyRatio;
  o.refinement_travel = m_RefinementTravel;
  o.gap = m_GapSize;
  o.refine_channels = m_RefineChannels;
  o.coarse_levels = static_cast<int>(m_NumberOfCoarseLevels);
  o.voxel_seed = m_VoxelSeed;
  o.fill_cavities = m_FillCavities;
  o.subvoxel_fit = m_SubvoxelFit;
  o.curvature_correction = m_CurvatureCorrection;
  o.sharp_edges = m_SharpEdges;
  o.fit_passes = static_cast<int>(std::min<unsigned int>(m_NumberOfFitPasses, 1000000u));
  o.fit_max_distance = m_FitMaximumDistance;
  o.fit_smoothing = m_FitSmoothing;
  o.lod_tolerance = m_LevelOfDetailTolerance;
  o.lod_min_angle = m_LevelOfDetailMinimumAngle;
  o.lod_rounds = static_cast<int>(std::min<unsigned int>(m_LevelOfDetailRounds, 1000000u));
  o.min_angle = m_MinimumAngle;
  o.face_budget = static_cast<std::size_t>(m_FaceBudget);
  o.float_exact_output = m_FloatExactOutput;
  return o;
}

template <typename TInputImage, typename TOutputMesh>
void
GeometricallyDeformedModelImageToMeshFilter<TInputImage, TOutputMesh>::SetCurrentCycleReport(
  const gdm::CycleReport & report)
{
  m_CurrentCycle = static_cast<SizeValueType>(std::max(report.cycle, 0));
  m_CurrentStage = static_cast<SizeValueType>(std::max(report.stage, 0));
  m_CurrentNumberOfVertices = static_cast<SizeValueType>(report.vertices);
  m_CurrentNumberOfFaces = static_cast<SizeValueType>(report.faces);
  m_CurrentNumberOfMovingVertices = static_cast<SizeValueType>(report.moved);
  m_CurrentNumberOfActiveVertices = static_cast<SizeValueType>(report.evaluated);
  m_CurrentNumberOfSplits = static_cast<SizeValueType>(report.splits);
  m_CurrentMeanCost = report.mean_cost;
}

template <typename TInputImage, typename TOutputMesh>
void
GeometricallyDeformedModelImageToMeshFilter<TInputImage, TOutputMesh>::GenerateData()
{
  m_StopReason.clear();
  m_NumberOfCycles = 0;
  m_NumberOfGlobalRefinementsPerformed = 0;
  m_NumberOfRejectedMoves = 0;
  m_NumberOfFlips = 0;
  m_NumberOfBorderVertices = 0;
  m_NumberOfFitMoves = 0;
  m_NumberOfLevelOfDetailSplits = 0;
  m_NumberOfLevelOfDetailCollapses = 0;
  m_NumberOfFloatRefusedVertices = 0;
  m_NumberOfBudgetCollapses = 0;
  m_NumberOfGapClosedVoxels = 0;
  m_NumberOfBridgeVertices = 0;
  m_NumberOfFilledCavities = 0;
  m_FilledCavityVolume = 0.0;
  m_NumberOfCavitiesBehindNarrowOpenings = 0;
  m_NumberOfCappedHandles = 0;
  m_NumberOfCavityComponents = 0;
  m_Genus = 0;
  m_NumberOfComponents = 0;
  m_NumberOfContactRegions = 0;
  m_ContactArea = 0.0;
  m_SeamArea = 0.0;
  this->SetCurrentCycleReport(gdm::CycleReport{});

  if constexpr (InputImageDimension != 3)
  {
    itkExceptionMacro(<< "the input image must be 3D, got a " << InputImageDimension << "D image");
  }
  else
  {
    const InputImageType * image = this->GetInput();
    OutputMeshType *       output = this->GetOutput();
    if (image == nullptr)
    {
      itkExceptionMacro(<< "no input image");
    }

    // The core's pipeline (gdm/pipeline.h), the code path of every front end:
    // the seed is checked (inside the volume and the object, a seed mesh
    // closed, manifold, outward and free of self-intersections), the model
    // deformed and measured. A model at the volume's border is this filter's
    // user's to judge (GetNumberOfBorderVertices).
    gdm::PipelineOptions pipeline;
    pipeline.deform = this->GetDeformOptions();
    pipeline.threshold_otsu = false;
    pipeline.threshold = pipeline.deform.threshold;
    pipeline.allow_border = true;
    std::exception_ptr observerError;
    const gdm::PipelineObserver observer = [&](const gdm::PipelineProgress & p) -> bool {
      try
      {
        // The cycle's figures, readable by ProgressEvent observers.
        this->SetCurrentCycleReport(p.cycle);
        this->UpdateProgress(static_cast<float>(p.fraction));
        return !this->GetAbortGenerateData();
      }
      catch (...)
      {
        observerError = std::current_exception();
        return false;
      }
    };

    gdm::PipelineResult pipelineResult;
    try
    {
      const gdm::Volume volume = GDMConversion::VolumeFromImage(image);
      if (const SeedMeshType * seedMesh = this->GetSeedMesh())
      {
        pipeline.seed.kind = gdm::SeedKind::mesh;
        pipeline.seed.mesh = GDMConversion::MeshFromITKMesh(seedMesh);
      }
      else
      {
        if (!(m_SeedRadius > 0.0))
        {
          itkExceptionMacro(<< "no seed: set SeedCenter and a positive SeedRadius, or a seed mesh with SetSeedMesh()");
        }
        pipeline.seed.kind = gdm::SeedKind::point;
        pipeline.seed.point = gdm::Vec3(m_SeedCenter[0], m_SeedCenter[1], m_SeedCenter[2]);
        pipeline.seed.radius = m_SeedRadius;
        pipeline.seed.level = static_cast<int>(m_SeedSubdivisionLevel);
      }
      pipelineResult = gdm::extract_surface(volume, pipeline, observer);
    }
    catch (const gdm::Error & error)
    {
      itkExceptionMacro(<< error.what());
    }
    if (observerError)
    {
      std::rethrow_exception(observerError);
    }
    const gdm::DeformResult & result = pipelineResult.deform;
    const gdm::Mesh &         mesh = pipelineResult.mesh;

    m_StopReason = gdm::to_string(result.reason);
    m_NumberOfCycles = static_cast<SizeValueType>(result.cycles);
    m_NumberOfGlobalRefinementsPerformed = static_cast<SizeValueType>(result.global_refinements);
    m_NumberOfRejectedMoves = static_cast<SizeValueType>(result.rejected_moves);
    m_NumberOfFlips = static_cast<SizeValueType>(result.flips);
    m_NumberOfBorderVertices = static_cast<SizeValueType>(result.border_vertices);
    m_NumberOfFitMoves = static_cast<SizeValueType>(result.fit_moves);
    m_NumberOfLevelOfDetailSplits = static_cast<SizeValueType>(result.lod_splits);
    m_NumberOfLevelOfDetailCollapses = static_cast<SizeValueType>(result.lod_collapses);
    m_NumberOfFloatRefusedVertices = static_cast<SizeValueType>(result.float_refused);
    m_NumberOfBudgetCollapses = static_cast<SizeValueType>(result.budget_collapses);
    m_NumberOfGapClosedVoxels = static_cast<SizeValueType>(result.gap_closed_voxels);
    m_NumberOfBridgeVertices = static_cast<SizeValueType>(result.bridge_vertices);
    m_NumberOfFilledCavities = static_cast<SizeValueType>(result.cavities);
    m_FilledCavityVolume = result.cavity_volume;
    m_NumberOfCavitiesBehindNarrowOpenings = static_cast<SizeValueType>(result.cavities_behind_openings);
    m_NumberOfCappedHandles = static_cast<SizeValueType>(result.handles);
    m_NumberOfCavityComponents = static_cast<SizeValueType>(result.cavity_components);
    m_Genus = static_cast<SizeValueType>(std::max(0, pipelineResult.report.genus));
    m_NumberOfComponents = static_cast<SizeValueType>(std::max(0, pipelineResult.report.components));
    m_NumberOfContactRegions = static_cast<SizeValueType>(pipelineResult.contacts.regions.size());
    m_ContactArea = pipelineResult.contacts.area;
    m_SeamArea = pipelineResult.contacts.seam_area;

    if (result.reason == gdm::StopReason::cancelled || this->GetAbortGenerateData())
    {
      ProcessAborted aborted(__FILE__, __LINE__);
      aborted.SetLocation(ITK_LOCATION);
      aborted.SetDescription("GeometricallyDeformedModelImageToMeshFilter: the deformation was aborted after " +
                             std::to_string(result.cycles) + " cycles");
      throw aborted;
    }

    try
    {
      GDMConversion::MeshToITKMesh(mesh, output);
      // The whole mesh is the buffered region (or the pipeline runs again).
      output->SetBufferedRegion(output->GetRequestedRegion());
    }
    catch (const gdm::Error & error)
    {
      itkExceptionMacro(<< error.what());
    }
    this->UpdateProgress(1.0f);
  }
}

template <typename TInputImage, typename TOutputMesh>
void
GeometricallyDeformedModelImageToMeshFilter<TInputImage, TOutputMesh>::PrintSelf(std::ostream & os,
                                                                                  Indent         indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "CatalogueOptions (every option by its catalogue name):";
  const gdm::DeformOptions options = this->GetDeformOptions();
  for (const auto & option : gdm::deform_option_catalogue())
  {
    os << " " << option.name << "=" << gdm::value_text(option, option.get(options));
  }
  os << std::endl;
  os << indent << "SeedMesh: " << (this->GetSeedMesh() ? "set" : "(none)") << std::endl;
  os << indent << "Threshold: " << m_Threshold << std::endl;
  os << indent << "Polarity: " << m_Polarity << std::endl;
  os << indent << "Mode: " << m_Mode << std::endl;
  os << indent << "DeformationWeight: " << m_DeformationWeight << std::endl;
  os << indent << "ImageEventWeight: " << m_ImageEventWeight << std::endl;
  os << indent << "TopologyWeight: " << m_TopologyWeight << std::endl;
  os << indent << "IntensityScale: " << m_IntensityScale << std::endl;
  os << indent << "Reach: " << m_Reach << std::endl;
  os << indent << "NormalRings: " << m_NormalRings << std::endl;
  os << indent << "LocalFlip: " << (m_LocalFlip ? "On" : "Off") << std::endl;
  os << indent << "MinimumStep: " << m_MinimumStep << std::endl;
  os << indent << "MaximumStep: " << m_MaximumStep << std::endl;
  os << indent << "MaximumStepReductions: " << m_MaximumStepReductions << std::endl;
  os << indent << "GradientStep: " << m_GradientStep << std::endl;
  os << indent << "LevelOfDetailFaceArea: " << m_LevelOfDetailFaceArea << std::endl;
  os << indent << "LevelOfDetailTopologyExtent: " << (m_LevelOfDetailTopologyExtent ? "On" : "Off") << std::endl;
  os << indent << "NumberOfGlobalRefinements: " << m_NumberOfGlobalRefinements << std::endl;
  os << indent << "MaximumNumberOfCycles: " << m_MaximumNumberOfCycles << std::endl;
  os << indent << "ConvergenceTolerance: " << m_ConvergenceTolerance << std::endl;
  os << indent << "ConvergenceWindow: " << m_ConvergenceWindow << std::endl;
  os << indent << "PreventSelfIntersection: " << (m_PreventSelfIntersection ? "On" : "Off") << std::endl;
  os << indent << "ImproveTriangles: " << (m_ImproveTriangles ? "On" : "Off") << std::endl;
  os << indent << "FlipMaximumDihedralAngle: " << m_FlipMaximumDihedralAngle << std::endl;
  os << indent << "MaximumNumberOfFaces: " << m_MaximumNumberOfFaces << std::endl;
  os << indent << "MaximumTopologyRatio: " << m_MaximumTopologyRatio << std::endl;
  os << indent << "RefinementTravel: " << m_RefinementTravel << std::endl;
  os << indent << "GapSize: " << m_GapSize << std::endl;
  os << indent << "RefineChannels: " << (m_RefineChannels ? "On" : "Off") << std::endl;
  os << indent << "NumberOfCoarseLevels: " << m_NumberOfCoarseLevels << std::endl;
  os << indent << "VoxelSeed: " << (m_VoxelSeed ? "On" : "Off") << std::endl;
  os << indent << "FillCavities: " << m_FillCavities << std::endl;
  os << indent << "SubvoxelFit: " << (m_SubvoxelFit ? "On" : "Off") << std::endl;
  os << indent << "CurvatureCorrection: " << (m_CurvatureCorrection ? "On" : "Off") << std::endl;
  os << indent << "SharpEdges: " << (m_SharpEdges ? "On" : "Off") << std::endl;
  os << indent << "NumberOfFitPasses: " << m_NumberOfFitPasses << std::endl;
  os << indent << "FitMaximumDistance: " << m_FitMaximumDistance << std::endl;
  os << indent << "FitSmoothing: " << m_FitSmoothing << std::endl;
  os << indent << "LevelOfDetailTolerance: " << m_LevelOfDetailTolerance << std::endl;
  os << indent << "LevelOfDetailMinimumAngle: " << m_LevelOfDetailMinimumAngle << std::endl;
  os << indent << "LevelOfDetailRounds: " << m_LevelOfDetailRounds << std::endl;
  os << indent << "MinimumAngle: " << m_MinimumAngle << std::endl;
  os << indent << "FaceBudget: " << m_FaceBudget << std::endl;
  os << indent << "FloatExactOutput: " << (m_FloatExactOutput ? "On" : "Off") << std::endl;
  os << indent << "SeedCenter: " << m_SeedCenter << std::endl;
  os << indent << "SeedRadius: " << m_SeedRadius << std::endl;
  os << indent << "SeedSubdivisionLevel: " << m_SeedSubdivisionLevel << std::endl;
  os << indent << "StopReason: " << (m_StopReason.empty() ? "(not run)" : m_StopReason) << std::endl;
  os << indent << "NumberOfCycles: " << m_NumberOfCycles << std::endl;
  os << indent << "NumberOfGlobalRefinementsPerformed: " << m_NumberOfGlobalRefinementsPerformed << std::endl;
  os << indent << "NumberOfRejectedMoves: " << m_NumberOfRejectedMoves << std::endl;
  os << indent << "NumberOfFlips: " << m_NumberOfFlips << std::endl;
  os << indent << "NumberOfBorderVertices: " << m_NumberOfBorderVertices << std::endl;
  os << indent << "NumberOfFitMoves: " << m_NumberOfFitMoves << std::endl;
  os << indent << "NumberOfLevelOfDetailSplits: " << m_NumberOfLevelOfDetailSplits << std::endl;
  os << indent << "NumberOfLevelOfDetailCollapses: " << m_NumberOfLevelOfDetailCollapses << std::endl;
  os << indent << "NumberOfFloatRefusedVertices: " << m_NumberOfFloatRefusedVertices << std::endl;
  os << indent << "NumberOfBudgetCollapses: " << m_NumberOfBudgetCollapses << std::endl;
  os << indent << "NumberOfGapClosedVoxels: " << m_NumberOfGapClosedVoxels << std::endl;
  os << indent << "NumberOfBridgeVertices: " << m_NumberOfBridgeVertices << std::endl;
  os << indent << "NumberOfFilledCavities: " << m_NumberOfFilledCavities << std::endl;
  os << indent << "FilledCavityVolume: " << m_FilledCavityVolume << std::endl;
  os << indent << "NumberOfCavitiesBehindNarrowOpenings: " << m_NumberOfCavitiesBehindNarrowOpenings << std::endl;
  os << indent << "NumberOfCappedHandles: " << m_NumberOfCappedHandles << std::endl;
  os << indent << "NumberOfCavityComponents: " << m_NumberOfCavityComponents << std::endl;
  os << indent << "Genus: " << m_Genus << std::endl;
  os << indent << "NumberOfComponents: " << m_NumberOfComponents << std::endl;
  os << indent << "NumberOfContactRegions: " << m_NumberOfContactRegions << std::endl;
  os << indent << "ContactArea: " << m_ContactArea << std::endl;
  os << indent << "SeamArea: " << m_SeamArea << std::endl;
  os << indent << "CurrentCycle: " << m_CurrentCycle << std::endl;
  os << indent << "CurrentStage: " << m_CurrentStage << std::endl;
  os << indent << "CurrentNumberOfVertices: " << m_CurrentNumberOfVertices << std::endl;
  os << indent << "CurrentNumberOfFaces: " << m_CurrentNumberOfFaces << std::endl;
  os << indent << "CurrentNumberOfMovingVertices: " << m_CurrentNumberOfMovingVertices << std::endl;
  os << indent << "CurrentNumberOfActiveVertices: " << m_CurrentNumberOfActiveVertices << std::endl;
  os << indent << "CurrentNumberOfSplits: " << m_CurrentNumberOfSplits << std::endl;
  os << indent << "CurrentMeanCost: " << m_CurrentMeanCost << std::endl;
}

} // end namespace itk

#endif // itkGeometricallyDeformedModelImageToMeshFilter_hxx
