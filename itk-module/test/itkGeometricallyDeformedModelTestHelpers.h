// Helpers shared by the module's tests (not part of the module's API).
#ifndef itkGeometricallyDeformedModelTestHelpers_h
#define itkGeometricallyDeformedModelTestHelpers_h

#include <cmath>
#include <functional>
#include <string>

#include "itkImage.h"
#include "itkImageRegionIteratorWithIndex.h"

namespace gdmtest
{

/** The message of the itk::ExceptionObject thrown by `f`, or "" when none is. */
inline std::string
ExceptionText(const std::function<void()> & f)
{
  try
  {
    f();
  }
  catch (const itk::ExceptionObject & e)
  {
    return e.GetDescription();
  }
  return "";
}

/** A CT-like ball: background + contrast * clamp(0.5 - d / edge, 0, 1), with d
 * the signed distance (mm) to the sphere (center, radius) in physical space. */
template <typename TImage>
void
FillBall(TImage * image, const typename TImage::PointType & center, double radius, double background = 50.0,
         double contrast = 150.0, double edge = 1.6)
{
  itk::ImageRegionIteratorWithIndex<TImage> it(image, image->GetBufferedRegion());
  for (it.GoToBegin(); !it.IsAtEnd(); ++it)
  {
    typename TImage::PointType p;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), p);
    const double d = p.EuclideanDistanceTo(center) - radius;
    const double t = std::min(1.0, std::max(0.0, 0.5 - d / edge));
    it.Set(static_cast<typename TImage::PixelType>(std::lround(background + contrast * t)));
  }
}

} // namespace gdmtest

#endif
