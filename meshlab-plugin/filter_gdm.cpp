// The plugin class: names, help, parameters and dispatch. The work is in
// gdm_bridge.cpp (CMeshO <-> gdm::Mesh and calls into the gdm core).
#include "filter_gdm.h"

#include <exception>

#include "gdm/errors.h"
#include "gdm_bridge.h"

namespace {

const char *const kReference =
	"<br><br>See: <i>James V. Miller, David E. Breen, William E. Lorensen, Robert M. O'Bara, Michael J. Wozny</i><br>"
	"<b>\"Geometrically Deformed Models: A Method for Extracting Closed Geometric Models from Volume Data\"</b><br>"
	"Computer Graphics (SIGGRAPH '91), 25(4), pages 217-226.";

// The deformation parameters every filter has (addWeightParameters).
void read_model_params(const RichParameterList &par, gdm_meshlab::ModelParams &m)
{
	m.a0 = par.getFloat("a0");
	m.a1 = par.getFloat("a1");
	m.a2 = par.getFloat("a2");
	m.lod_face_area = par.getFloat("LevelOfDetail");
	m.global_refinements = par.getInt("GlobalRefinements");
	m.max_cycles = par.getInt("MaxCycles");
}

gdm_meshlab::VolumeParams volumeParams(const RichParameterList &par)
{
	gdm_meshlab::VolumeParams v;
	v.volume_file = par.getString("VolumeFile").toStdString();
	v.auto_threshold = par.getBool("AutoThreshold");
	v.threshold = par.getFloat("Threshold");
	v.object_darker = par.getEnum("Polarity") == 1;
	v.smoothing_sigma = par.getFloat("Smoothing");
	read_model_params(par, v);
	v.subvoxel_fit = par.getBool("SubvoxelFit");
	v.fit_smoothing = par.getFloat("FitSmoothing");
	v.lod_tolerance = par.getFloat("ErrorTolerance");
	return v;
}

}  // namespace

FilterGdmPlugin::FilterGdmPlugin()
{
	typeList << FP_GDM_FROM_VOLUME << FP_GDM_DEFORM_MESH << FP_GDM_SHRINK_WRAP;
	for (FilterIDType tt : types())
		actionList << new QAction(filterName(tt), this);
}

QString FilterGdmPlugin::pluginName() const
{
	return "FilterGDM";
}

QString FilterGdmPlugin::filterName(FilterIDType filterId) const
{
	switch (filterId) {
	case FP_GDM_FROM_VOLUME: return "Geometrically Deformed Model from Volume";
	case FP_GDM_DEFORM_MESH: return "Deform Current Mesh into Volume";
	case FP_GDM_SHRINK_WRAP: return "Shrink-Wrap Current Mesh";
	default: assert(0); return "";
	}
}

QString FilterGdmPlugin::filterInfo(FilterIDType filterId) const
{
	switch (filterId) {
	case FP_GDM_FROM_VOLUME:
		return QString("Extracts a closed triangle mesh of an object in a volume (MetaImage .mha/.mhd, NRRD, NIfTI "
			"or a DICOM directory) with a Geometrically Deformed Model: a small icosahedron placed inside the object "
			"grows until it meets the threshold, split into faces no larger than the level of detail as it goes. "
			"The result is closed, 2-manifold, of genus 0 and free of self-intersections. Each vertex stores in its "
			"quality the deformation cycle that created it (Fig. 11 of the paper): colour by vertex quality to see it.")
			+ kReference;
	case FP_GDM_DEFORM_MESH:
		return QString("Uses the current layer as the seed of a Geometrically Deformed Model in a volume file. The "
			"layer must be a closed 2-manifold triangle mesh lying inside the object (grow) or around it (shrink). "
			"The result replaces the layer or is added as a new one. Vertex quality holds the generation.")
			+ kReference;
	case FP_GDM_SHRINK_WRAP:
		return QString("Wraps the current layer (any triangles: holes, several pieces, noise; or a point cloud) in a "
			"closed, 2-manifold, genus-0, self-intersection-free mesh: a sphere around the layer shrinks onto the "
			"distance field of the layer (the paper's \"shrink wrap collapsing around an object\", section 1). "
			"Holes and gaps smaller than the level of detail are bridged. Where input is left beyond 90% of the "
			"tolerance (a crevice narrower than the wrap's faces), the wrap is refined there and shrunk again, at "
			"most 4 times. The log gives the wrap's faces, volume and its largest distances to the input.")
			+ kReference;
	default: assert(0); return "Unknown Filter";
	}
}

FilterGdmPlugin::FilterClass FilterGdmPlugin::getClass(QAction *a)
{
	switch (ID(a)) {
	case FP_GDM_FROM_VOLUME: return MeshFilterInterface::MeshCreation;
	case FP_GDM_DEFORM_MESH:
	case FP_GDM_SHRINK_WRAP: return MeshFilterInterface::Remeshing;
	default: assert(0); return MeshFilterInterface::Generic;
	}
}

MeshFilterInterface::FILTER_ARITY FilterGdmPlugin::filterArity(QAction *a) const
{
	switch (ID(a)) {
	case FP_GDM_FROM_VOLUME: return NONE;
	default: return SINGLE_MESH;
	}
}

int FilterGdmPlugin::getPreConditions(QAction *a) const
{
	switch (ID(a)) {
	case FP_GDM_FROM_VOLUME: return MeshModel::MM_NONE;
	case FP_GDM_DEFORM_MESH: return MeshModel::MM_FACENUMBER;
	case FP_GDM_SHRINK_WRAP: return MeshModel::MM_VERTCOORD;
	default: return MeshModel::MM_NONE;
	}
}

int FilterGdmPlugin::postCondition(QAction *a) const
{
	switch (ID(a)) {
	case FP_GDM_SHRINK_WRAP: return MeshModel::MM_NONE;  // the input layer is not touched
	default: return MeshModel::MM_VERTCOORD | MeshModel::MM_VERTNUMBER | MeshModel::MM_FACENUMBER |
			MeshModel::MM_VERTQUALITY | MeshModel::MM_FACENORMAL | MeshModel::MM_VERTNORMAL;
	}
}

int FilterGdmPlugin::getRequirements(QAction *)
{
	return MeshModel::MM_NONE;
}

void FilterGdmPlugin::addVolumeParameters(RichParameterList &par)
{
	par.addParam(RichString("VolumeFile", "", "Volume file",
		"Path of the volume: a .mha, .mhd, .nrrd, .nhdr, .nii or .nii.gz file, or a directory holding one DICOM "
		"series. Read with ITK; coordinates are physical (mm), as in the file."));
	par.addParam(RichFloat("Threshold", 0.0f, "Threshold T",
		"The intensity that separates the object from the background (T of eq. 2 in the paper), in the volume's "
		"units (e.g. Hounsfield units for CT)."));
	par.addParam(RichBool("AutoThreshold", false, "Threshold at mid-range",
		"Ignore Threshold and use the midpoint between the volume's smallest and largest values."));
	par.addParam(RichEnum("Polarity", 0, QStringList() << "Object brighter than T" << "Object darker than T",
		"Polarity", "Which side of the threshold is the object."));
	par.addParam(RichFloat("Smoothing", 0.0f, "Smoothing sigma (mm)",
		"Standard deviation of a Gaussian applied to the volume before the deformation, in mm; 0 turns it off. "
		"Helps on noisy scans."));
}

void FilterGdmPlugin::addWeightParameters(RichParameterList &par, const QString &lodUnit)
{
	par.addParam(RichFloat("a0", 1.0f, "a0 (deformation)",
		"Weight of the deformation potential D (normal tracking, section 3.1.1): how strongly each vertex is "
		"pushed along its normal. Paper's default: 1."));
	par.addParam(RichFloat("a1", 1.0f, "a1 (image event)",
		"Weight of the image event term I (the shifted threshold, eq. 2): how strongly the threshold stops the "
		"model. Paper's default: 1."));
	par.addParam(RichFloat("a2", 5.0f, "a2 (topology)",
		"Weight of the topology term T (eq. 3): keeps the surface locally smooth and bridges gaps smaller than "
		"the level of detail. Paper's default: 5."));
	par.addParam(RichFloat("LevelOfDetail", 10.0f, "Level of detail (face area, " + lodUnit + ")",
		"Faces larger than this area are split while the model deforms (section 4). Smaller values follow finer "
		"detail with more faces. Paper's default: 10 " + lodUnit + "."));
	par.addParam(RichInt("GlobalRefinements", 1, "Global refinements",
		"After each convergence every face is split 1-to-4 and the model converges again, this many times "
		"(section 6, 0 to 4)."));
	par.addParam(RichInt("MaxCycles", 2000, "Maximum cycles",
		"Hard limit on the number of deformation cycles, all refinements together."));
}

void FilterGdmPlugin::addAccuracyParameters(RichParameterList &par, const QString &lodUnit)
{
	par.addParam(RichBool("SubvoxelFit", true, "Sub-voxel final fit",
		"Beyond the paper: after the last convergence every vertex moves along its normal onto the threshold "
		"crossing of the trilinear field (at most 1 " + lodUnit.section('^', 0, 0) + "), every move checked "
		"against self-intersection. Removes the quarter-voxel shortfall of the smallest step and the "
		"curvature term's inward pull. Default: on."));
	par.addParam(RichFloat("FitSmoothing", 0.5f, "Fit smoothing (0 = off)",
		"Beyond the paper: noise-adaptive smoothing of the sub-voxel fit. Each vertex is also drawn toward the "
		"quadric fitted over its two rings of neighbours, the more so the closer it stands to it compared with "
		"this many times the image noise measured on the model: noise is smoothed away without shrinking "
		"spheres or tubes, while edges and corners keep their data. 0 to 5; 0 follows the data alone. "
		"Default: 0.5."));
	par.addParam(RichFloat("ErrorTolerance", 0.0f, "Error tolerance (" + lodUnit.section('^', 0, 0) + ", 0 = off)",
		"Beyond the paper: error-driven level of detail. Faces whose surface deviates from the threshold surface "
		"by more than this are split; edges are collapsed where the new faces stay within half of it (few faces "
		"on flat parts, more along edges and tight bends), keeping the mesh closed, 2-manifold, genus 0 and free "
		"of self-intersections. E.g. 0.1 asks for at most a tenth of a " + lodUnit.section('^', 0, 0) +
		" of error. 0 keeps the face-area level of detail only. Default: 0 (off)."));
}

void FilterGdmPlugin::initParameterSet(QAction *action, MeshDocument &md, RichParameterList &par)
{
	// The creation filter runs without any layer: md.mm() may be null.
	initParameters(action, md.mm(), par);
}

void FilterGdmPlugin::initParameterSet(QAction *action, MeshModel &m, RichParameterList &par)
{
	initParameters(action, &m, par);
}

void FilterGdmPlugin::initParameters(QAction *action, const MeshModel *m, RichParameterList &par)
{
	switch (ID(action)) {
	case FP_GDM_FROM_VOLUME:
		addVolumeParameters(par);
		par.addParam(RichBool("SeedAtCenter", true, "Seed at the volume's centre",
			"Place the seed at the centre of the volume's physical extent instead of at Seed point."));
		par.addParam(RichPoint3f("SeedPoint", Point3m(0, 0, 0), "Seed point (mm)",
			"Centre of the seed icosahedron, in physical coordinates (mm); it must lie inside the object."));
		par.addParam(RichFloat("SeedRadius", 3.0f, "Seed radius (mm)",
			"Radius of the seed icosahedron (mm). The seed must touch the object's side of the threshold."));
		addWeightParameters(par, "voxel^2");
		addAccuracyParameters(par, "voxel^2");
		break;
	case FP_GDM_DEFORM_MESH:
		addVolumeParameters(par);
		par.addParam(RichEnum("Mode", 0, QStringList() << "Grow (the layer is inside the object)"
			<< "Shrink (the layer encloses the object)", "Mode",
			"Grow the layer outwards from inside the object, or shrink it onto the object from outside (section 5)."));
		par.addParam(RichBool("NewLayer", true, "Add the result as a new layer",
			"Keep the current layer and add the deformed model as a new layer; otherwise replace the current layer."));
		addWeightParameters(par, "voxel^2");
		addAccuracyParameters(par, "voxel^2");
		break;
	case FP_GDM_SHRINK_WRAP: {
		const float diag = m != nullptr && m->cm.bbox.IsNull() == false ? m->cm.bbox.Diag() : 1.0f;
		par.addParam(RichAbsPerc("CellSize", diag / 100.0f, 0.0f, diag / 5.0f, "Grid cell size",
			"Size of the cells of the grid on which the distance to the mesh is sampled. The level of detail is "
			"measured in these cells. Default: 1% of the bounding box diagonal."));
		par.addParam(RichAbsPerc("Tolerance", diag / 50.0f, 0.0f, diag / 5.0f, "Tolerance",
			"Largest distance of the input from the wrap: the wrap settles at a third of this distance outside "
			"the input (so that concave creases down to about 40 degrees stay within it) and never crosses the "
			"input. At least the cell size. Default: 2% of the bounding box diagonal."));
		addWeightParameters(par, "cell^2");
		break;
	}
	default: assert(0);
	}
}

bool FilterGdmPlugin::fail(const QString &message)
{
	errorMessage = message;
	// meshlabserver prints the log, not errorMessage: give the message to both.
	Log(GLLogStream::WARNING, qUtf8Printable("Error: " + message));
	return false;
}

bool FilterGdmPlugin::applyFilter(QAction *action, MeshDocument &md, const RichParameterList &par,
	vcg::CallBackPos *cb)
{
	gdm_meshlab::LogLines log;
	const gdm_meshlab::Progress progress = [cb](int percent, const char *text) {
		return cb == nullptr || cb(percent, text);
	};
	const auto flushLog = [&]() {
		for (const std::string &line : log) Log(line.c_str());
		log.clear();
	};
	try {
		switch (ID(action)) {
		case FP_GDM_FROM_VOLUME: {
			gdm_meshlab::SeedParams seed;
			seed.at_volume_centre = par.getBool("SeedAtCenter");
			const Point3m p = par.getPoint3m("SeedPoint");
			seed.point = gdm::Vec3(p[0], p[1], p[2]);
			seed.radius = par.getFloat("SeedRadius");
			const gdm::Mesh mesh = gdm_meshlab::model_from_volume(volumeParams(par), seed, progress, &log);
			flushLog();
			MeshModel *mm = md.addNewMesh("", "Geometrically Deformed Model", true);
			mm->updateDataMask(MeshModel::MM_VERTQUALITY);
			gdm_meshlab::to_meshlab(mesh, mm->cm);
			mm->UpdateBoxAndNormals();
			return true;
		}
		case FP_GDM_DEFORM_MESH: {
			MeshModel *current = md.mm();
			if (current == nullptr) return fail("no current layer: open a closed triangle mesh to use as the seed");
			gdm::Mesh seed = gdm_meshlab::to_gdm_seed(current->cm, &log);
			gdm_meshlab::VolumeParams v = volumeParams(par);
			v.shrink = par.getEnum("Mode") == 1;
			const gdm::Mesh mesh = gdm_meshlab::deform_seed_in_volume(std::move(seed), v, progress, &log);
			flushLog();
			MeshModel *target = current;
			if (par.getBool("NewLayer"))
				target = md.addNewMesh("", current->label() + " deformed", true);
			target->updateDataMask(MeshModel::MM_VERTQUALITY);
			gdm_meshlab::to_meshlab(mesh, target->cm);
			target->UpdateBoxAndNormals();
			return true;
		}
		case FP_GDM_SHRINK_WRAP: {
			MeshModel *current = md.mm();
			if (current == nullptr) return fail("no current layer to wrap");
			gdm_meshlab::ModelParams m;
			read_model_params(par, m);
			gdm::WrapOptions w;
			w.cell_size = par.getAbsPerc("CellSize");
			w.tolerance = par.getAbsPerc("Tolerance");
			w.a0 = m.a0;
			w.a1 = m.a1;
			w.a2 = m.a2;
			w.lod_face_area = m.lod_face_area;
			w.global_refinements = m.global_refinements;
			w.max_cycles = m.max_cycles;
			const gdm::Mesh mesh =
				gdm_meshlab::shrink_wrap(gdm_meshlab::triangle_soup(current->cm), w, progress, &log);
			flushLog();
			MeshModel *mm = md.addNewMesh("", current->label() + " shrink-wrap", true);
			mm->updateDataMask(MeshModel::MM_VERTQUALITY);
			gdm_meshlab::to_meshlab(mesh, mm->cm);
			mm->UpdateBoxAndNormals();
			return true;
		}
		default:
			assert(0);
			return false;
		}
	} catch (const std::exception &e) {
		flushLog();
		return fail(QString::fromStdString(e.what()));
	}
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterGdmPlugin)
