// VTK part of the benchmark study (see peer_vtk.h). No gdm, ITK or CGAL header here.
#include "peer_vtk.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <vtkActor.h>
#include <vtkAxis.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextActor.h>
#include <vtkContextScene.h>
#include <vtkCoordinate.h>
#include <vtkFloatArray.h>
#include <vtkFlyingEdges3D.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkImageResample.h>
#include <vtkIntArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkQuadricDecimation.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSMPTools.h>
#include <vtkTable.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTriangleFilter.h>
#include <vtkWindowToImageFilter.h>
#include <vtkWindowedSincPolyDataFilter.h>

namespace study {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Flying edges at `level`, the surface only (no normals, gradients or scalars).
void extract_surface_at(vtkFlyingEdges3D* fe, double level) {
  fe->SetValue(0, level);
  fe->ComputeNormalsOff();
  fe->ComputeGradientsOff();
  fe->ComputeScalarsOff();
}

// Wraps the image's buffer without copying (VTK only reads it).
vtkSmartPointer<vtkImageData> to_vtk(const Image& image) {
  auto data = vtkSmartPointer<vtkImageData>::New();
  data->SetDimensions(image.dims[0], image.dims[1], image.dims[2]);
  data->SetSpacing(image.spacing.data());
  data->SetOrigin(image.origin.data());
  vtkNew<vtkFloatArray> scalars;
  scalars->SetName("values");
  scalars->SetVoidArray(const_cast<float*>(image.values.data()), static_cast<vtkIdType>(image.values.size()), 1);
  data->GetPointData()->SetScalars(scalars);
  return data;
}

Surface to_surface(vtkPolyData* poly) {
  Surface s;
  const vtkIdType n = poly->GetNumberOfPoints();
  s.points.resize(static_cast<std::size_t>(n));
  for (vtkIdType i = 0; i < n; ++i) poly->GetPoint(i, s.points[static_cast<std::size_t>(i)].data());
  vtkCellArray* polys = poly->GetPolys();
  vtkNew<vtkIdList> ids;
  s.faces.reserve(static_cast<std::size_t>(polys->GetNumberOfCells()));
  for (polys->InitTraversal(); polys->GetNextCell(ids);) {
    // Fan-triangulate anything that is not a triangle (flying edges only makes triangles).
    for (vtkIdType k = 1; k + 1 < ids->GetNumberOfIds(); ++k)
      s.faces.push_back({static_cast<int>(ids->GetId(0)), static_cast<int>(ids->GetId(k)),
                         static_cast<int>(ids->GetId(k + 1))});
  }
  return s;
}

vtkSmartPointer<vtkPolyData> to_poly(const Surface& s) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(s.points.size()));
  for (std::size_t i = 0; i < s.points.size(); ++i) points->SetPoint(static_cast<vtkIdType>(i), s.points[i].data());
  vtkNew<vtkCellArray> cells;
  for (const auto& f : s.faces) {
    const vtkIdType ids[3] = {f[0], f[1], f[2]};
    cells->InsertNextCell(3, ids);
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(cells);
  if (!s.generation.empty()) {
    vtkNew<vtkIntArray> gen;
    gen->SetName("generation");
    gen->SetNumberOfValues(static_cast<vtkIdType>(s.generation.size()));
    for (std::size_t i = 0; i < s.generation.size(); ++i) gen->SetValue(static_cast<vtkIdType>(i), s.generation[i]);
    poly->GetPointData()->SetScalars(gen);
  }
  return poly;
}

void write_window(vtkRenderWindow* window, const std::string& png) {
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(png.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
}

}  // namespace

void set_vtk_threads(int threads) { vtkSMPTools::Initialize(threads); }
std::string vtk_smp_backend() { return vtkSMPTools::GetBackend() ? vtkSMPTools::GetBackend() : "unknown"; }

PeerResult run_flying_edges(const Image& image, double threshold) {
  auto data = to_vtk(image);
  vtkNew<vtkFlyingEdges3D> fe;
  fe->SetInputData(data);
  extract_surface_at(fe, threshold);
  const auto t0 = Clock::now();
  fe->Update();
  PeerResult r;
  r.seconds = seconds_since(t0);
  r.surface = to_surface(fe->GetOutput());
  return r;
}

PeerResult run_slicer_chain(const Image& image, double threshold, std::size_t target_faces) {
  auto data = to_vtk(image);
  vtkNew<vtkFlyingEdges3D> fe;
  fe->SetInputData(data);
  extract_surface_at(fe, threshold);
  vtkNew<vtkWindowedSincPolyDataFilter> smooth;
  smooth->SetInputConnection(fe->GetOutputPort());
  smooth->SetNumberOfIterations(20);
  smooth->SetPassBand(std::pow(10.0, -4.0 * 0.5));
  smooth->BoundarySmoothingOff();
  smooth->FeatureEdgeSmoothingOff();
  smooth->NonManifoldSmoothingOn();
  smooth->NormalizeCoordinatesOn();
  const auto t0 = Clock::now();
  smooth->Update();
  PeerResult r;
  const vtkIdType faces = smooth->GetOutput()->GetNumberOfPolys();
  if (target_faces > 0 && faces > static_cast<vtkIdType>(target_faces)) {
    vtkNew<vtkQuadricDecimation> decimate;
    decimate->SetInputConnection(smooth->GetOutputPort());
    decimate->SetTargetReduction(1.0 - static_cast<double>(target_faces) / static_cast<double>(faces));
    decimate->VolumePreservationOn();
    decimate->Update();
    r.seconds = seconds_since(t0);
    r.surface = to_surface(decimate->GetOutput());
  } else {
    r.seconds = seconds_since(t0);
    r.surface = to_surface(smooth->GetOutput());
  }
  r.note = "target " + std::to_string(target_faces) + " faces";
  return r;
}

Surface iso_surface(const Image& image, double level, int upsample) {
  auto data = to_vtk(image);
  vtkNew<vtkImageResample> resample;
  resample->SetInputData(data);
  resample->SetInterpolationModeToLinear();
  for (int a = 0; a < 3; ++a) resample->SetAxisMagnificationFactor(a, upsample);
  vtkNew<vtkFlyingEdges3D> fe;
  fe->SetInputConnection(resample->GetOutputPort());
  extract_surface_at(fe, level);
  fe->Update();
  return to_surface(fe->GetOutput());
}

void render_panels(const std::string& png, const std::vector<Panel>& panels, int panel_size, int frame) {
  if (panels.empty()) return;
  const int n = static_cast<int>(panels.size());
  const int cols = std::min(n, 4);
  const int rows = (n + cols - 1) / cols;
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(cols * panel_size, rows * panel_size);
  window->SetMultiSamples(0);
  // One camera for all panels so that they are seen alike.
  vtkNew<vtkCamera> camera;
  double bounds[6] = {1e300, -1e300, 1e300, -1e300, 1e300, -1e300};
  std::vector<vtkSmartPointer<vtkRenderer>> renderers;
  for (int i = 0; i < n; ++i) {
    const Panel& p = panels[static_cast<std::size_t>(i)];
    vtkNew<vtkRenderer> renderer;
    const int c = i % cols, r = rows - 1 - i / cols;
    renderer->SetViewport(double(c) / cols, double(r) / rows, double(c + 1) / cols, double(r + 1) / rows);
    renderer->SetBackground(1.0, 1.0, 1.0);
    if (p.surface != nullptr && !p.surface->faces.empty()) {
      auto poly = to_poly(*p.surface);
      double b[6];
      poly->GetBounds(b);
      if (frame < 0 || frame == i)
      for (int a = 0; a < 3; ++a) {
        bounds[2 * a] = std::min(bounds[2 * a], b[2 * a]);
        bounds[2 * a + 1] = std::max(bounds[2 * a + 1], b[2 * a + 1]);
      }
      vtkNew<vtkPolyDataNormals> normals;
      normals->SetInputData(poly);
      normals->SplittingOff();
      normals->ConsistencyOff();
      normals->AutoOrientNormalsOff();
      vtkNew<vtkPolyDataMapper> mapper;
      mapper->SetInputConnection(normals->GetOutputPort());
      vtkNew<vtkActor> actor;
      actor->SetMapper(mapper);
      actor->GetProperty()->EdgeVisibilityOn();
      actor->GetProperty()->SetEdgeColor(0.15, 0.15, 0.15);
      actor->GetProperty()->SetLineWidth(0.5);
      if (p.by_generation && !p.surface->generation.empty()) {
        const auto mm = std::minmax_element(p.surface->generation.begin(), p.surface->generation.end());
        vtkNew<vtkLookupTable> lut;
        lut->SetHueRange(0.66, 0.0);
        lut->Build();
        mapper->SetLookupTable(lut);
        mapper->SetScalarRange(*mm.first, std::max(*mm.first + 1, *mm.second));
        mapper->ScalarVisibilityOn();
        mapper->SetInterpolateScalarsBeforeMapping(1);
      } else {
        mapper->ScalarVisibilityOff();
        actor->GetProperty()->SetColor(0.85, 0.75, 0.55);
      }
      renderer->AddActor(actor);
    }
    vtkNew<vtkTextActor> text;
    text->SetInput(p.title.c_str());
    text->GetTextProperty()->SetFontSize(15);
    text->GetTextProperty()->SetColor(0, 0, 0);
    text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    text->SetPosition(0.02, 0.02);
    renderer->AddViewProp(text);
    renderer->SetActiveCamera(camera);
    window->AddRenderer(renderer);
    renderers.push_back(renderer);
  }
  for (int i = n; i < rows * cols; ++i) {  // blank the unused slots
    vtkNew<vtkRenderer> renderer;
    const int c = i % cols, r = rows - 1 - i / cols;
    renderer->SetViewport(double(c) / cols, double(r) / rows, double(c + 1) / cols, double(r + 1) / rows);
    renderer->SetBackground(1.0, 1.0, 1.0);
    window->AddRenderer(renderer);
  }
  if (bounds[0] <= bounds[1]) {
    const double cx = 0.5 * (bounds[0] + bounds[1]), cy = 0.5 * (bounds[2] + bounds[3]), cz = 0.5 * (bounds[4] + bounds[5]);
    const double size = std::max({bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]});
    camera->SetFocalPoint(cx, cy, cz);
    camera->SetPosition(cx + 2.0 * size, cy - 2.4 * size, cz + 1.6 * size);
    camera->SetViewUp(0, 0, 1);
    camera->SetViewAngle(30.0);
    renderers.front()->ResetCameraClippingRange(bounds);
    camera->SetClippingRange(0.1 * size, 20.0 * size);
  }
  window->Render();
  write_window(window, png);
}

void line_plot(const std::string& png, const std::string& title, const std::string& x_label,
               const std::string& y_label, const std::vector<Series>& series, bool log_x, bool log_y) {
  // The chart in a context actor of a plain offscreen window, as render_panels
  // draws: a vtkContextView also brings an X interactor, which an offscreen
  // picture does not need.
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(760, 480);
  window->SetMultiSamples(0);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1.0, 1.0, 1.0);
  window->AddRenderer(renderer);
  vtkNew<vtkContextActor> context;
  context->GetScene()->SetRenderer(renderer);
  renderer->AddActor(context);
  vtkNew<vtkChartXY> chart;
  context->GetScene()->AddItem(chart);
  chart->SetTitle(title);
  chart->GetTitleProperties()->SetFontSize(16);
  chart->SetShowLegend(true);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(x_label);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(y_label);
  chart->GetAxis(vtkAxis::BOTTOM)->SetLogScale(log_x);
  chart->GetAxis(vtkAxis::LEFT)->SetLogScale(log_y);
  static const unsigned char colours[][3] = {{31, 119, 180}, {255, 127, 14}, {44, 160, 44}, {214, 39, 40},
                                             {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {127, 127, 127}};
  int index = 0;
  std::vector<vtkSmartPointer<vtkTable>> keep;
  for (const Series& s : series) {
    if (s.x.empty()) continue;
    std::vector<std::pair<double, double>> xy;
    for (std::size_t i = 0; i < s.x.size(); ++i)
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && (!log_x || s.x[i] > 0) && (!log_y || s.y[i] > 0))
        xy.emplace_back(s.x[i], s.y[i]);
    if (xy.empty()) continue;
    std::sort(xy.begin(), xy.end());
    auto table = vtkSmartPointer<vtkTable>::New();
    vtkNew<vtkFloatArray> xs, ys;
    xs->SetName("x");
    ys->SetName(s.name.c_str());
    for (const auto& [x, y] : xy) {
      xs->InsertNextValue(static_cast<float>(x));
      ys->InsertNextValue(static_cast<float>(y));
    }
    table->AddColumn(xs);
    table->AddColumn(ys);
    keep.push_back(table);
    vtkPlot* plot = chart->AddPlot(s.points_only || xy.size() == 1 ? vtkChart::POINTS : vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    const auto* c = colours[index++ % 8];
    plot->SetColor(c[0], c[1], c[2], 255);
    plot->SetWidth(2.0);
  }
  window->Render();
  write_window(window, png);
}

}  // namespace study
