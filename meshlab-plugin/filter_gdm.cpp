// The plugin class: names, help, parameters and dispatch. The work is in
// gdm_bridge.cpp (CMeshO <-> gdm::Mesh and calls into the gdm core).
#include "filter_gdm.h"

#include <exception>
#include <stdexcept>
#include <vector>

#include "gdm/errors.h"
#include "gdm_bridge.h"

namespace {

const char *const kReference =
	"<br><br>See: <i>James V. Miller, David E. Breen, William E. Lorensen, Robert M. O'Bara, Michael J. Wozny</i><br>"
	"<b>\"Geometrically Deformed Models: A Method for Extracting Closed Geometric Models from Volume Data\"</b><br>"
	"Computer Graphics (SIGGRAPH '91), 25(4), pages 217-226.";

// The catalogue's options each filter offers (gdm::pipeline_option_catalogue():
// the parameter is named as the option, its default, range and help are the
// catalogue's, and the pipeline checks its value).
const std::vector<const char *> kVolumeOptions = {"polarity", "smooth"};
const std::vector<const char *> kModelOptions = {"a0", "a1", "a2", "lod_face_area", "global_refinements",
	"max_cycles", "subvoxel_fit", "fit_smoothing", "lod_tolerance", "allow_border"};
const std::vector<const char *> kWrapModelOptions = {"a0", "a1", "a2", "lod_face_area", "global_refinements",
	"max_cycles"};

const gdm::OptionEntry<gdm::PipelineOptions> &catalogueOption(const std::string &name)
{
	for (const auto &o : gdm::pipeline_option_catalogue())
		if (o.name == name) return o;
	throw std::logic_error("no option " + name + " in the catalogue");
}

// One parameter from the catalogue; `unit` replaces the catalogue's unit (the
// wrap measures in grid cells, not voxels).
void addOption(RichParameterList &par, const char *name, const QString &unit = QString())
{
	const auto &o = catalogueOption(name);
	const gdm::PipelineOptions defaults;
	const double value = o.get(defaults);
	const QString shownUnit = unit.isEmpty() ? QString::fromStdString(o.unit) : unit;
	QString help = QString::fromStdString(o.help);
	help += " (" + (shownUnit.isEmpty() ? QString() : shownUnit + "; ") + QString::fromStdString(gdm::range_text(o)) +
		"; default " + QString::fromStdString(gdm::value_text(o, value)) + ")";
	const QString label = QString::fromStdString(o.name) + (shownUnit.isEmpty() ? QString() : " (" + shownUnit + ")");
	switch (o.type) {
	case gdm::OptionType::real:
		par.addParam(RichFloat(name, static_cast<float>(value), label, help));
		break;
	case gdm::OptionType::integer:
		par.addParam(RichInt(name, static_cast<int>(value), label, help));
		break;
	case gdm::OptionType::boolean:
		par.addParam(RichBool(name, value != 0.0, label, help));
		break;
	case gdm::OptionType::choice: {
		QStringList choices;
		for (const auto &c : o.choices) choices << QString::fromStdString(c);
		par.addParam(RichEnum(name, static_cast<int>(value), choices, label, help));
		break;
	}
	}
}

void readOptions(const RichParameterList &par, const std::vector<const char *> &names, gdm::PipelineOptions &options)
{
	for (const char *name : names) {
		const auto &o = catalogueOption(name);
		switch (o.type) {
		case gdm::OptionType::real: o.set(options, par.getFloat(name)); break;
		case gdm::OptionType::integer: o.set(options, par.getInt(name)); break;
		case gdm::OptionType::boolean: o.set(options, par.getBool(name) ? 1.0 : 0.0); break;
		case gdm::OptionType::choice: o.set(options, par.getEnum(name)); break;
		}
	}
}

// What the two volume filters share: the volume, its threshold, the catalogue's options.
gdm::PipelineOptions volumeOptions(const RichParameterList &par)
{
	gdm::PipelineOptions o;
	o.threshold_otsu = par.getBool("threshold_otsu");
	o.threshold = par.getFloat("threshold");
	readOptions(par, kVolumeOptions, o);
	readOptions(par, kModelOptions, o);
	return o;
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
			"or a DICOM directory) with a Geometrically Deformed Model: a seed sphere inside the object (by default at "
			"the deepest point of the largest object region, with Otsu's threshold: the gdm command's defaults, the "
			"same pipeline and the same mesh) grows until it meets the threshold, split into faces no larger than the "
			"level of detail as it goes. "
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
	par.addParam(RichString("volume_file", "", "Volume file",
		"Path of the volume: a .mha, .mhd, .nrrd, .nhdr, .nii, .nii.gz or .vtk file, or a directory holding DICOM "
		"series (the one with most slices). Read with ITK as the gdm command reads it; coordinates are physical (mm)."));
	par.addParam(RichBool("threshold_otsu", true, "Otsu's threshold",
		"Choose the threshold T by Otsu's method (256 bins) on the (smoothed) volume, as the gdm command does by "
		"default; off: use the threshold below."));
	par.addParam(RichFloat("threshold", 0.0f, "threshold (image units)",
		"The intensity that separates the object from the background (T of eq. 2 in the paper), in the volume's "
		"units (e.g. Hounsfield units for CT). Used when Otsu's threshold is off."));
	for (const char *name : kVolumeOptions) addOption(par, name);
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
		par.addParam(RichBool("seed_automatic", true, "Automatic seed",
			"Seed at the deepest point of the largest object region (a sphere of half its depth), as the gdm "
			"command's --seed auto; off: a sphere at seed_point."));
		par.addParam(RichPoint3f("seed_point", Point3m(0, 0, 0), "seed_point (mm)",
			"Centre of the seed sphere in physical coordinates (mm) when the automatic seed is off; it must lie "
			"inside the object."));
		addOption(par, "seed_radius");
		for (const char *name : kModelOptions) addOption(par, name);
		break;
	case FP_GDM_DEFORM_MESH:
		addVolumeParameters(par);
		addOption(par, "mode");
		par.addParam(RichBool("new_layer", true, "Add the result as a new layer",
			"Keep the current layer and add the deformed model as a new layer; otherwise replace the current layer."));
		for (const char *name : kModelOptions) addOption(par, name);
		break;
	case FP_GDM_SHRINK_WRAP: {
		const float diag = m != nullptr && m->cm.bbox.IsNull() == false ? m->cm.bbox.Diag() : 1.0f;
		par.addParam(RichAbsPerc("cell_size", diag / 100.0f, 0.0f, diag / 5.0f, "Grid cell size",
			"Size of the cells of the grid on which the distance to the mesh is sampled. The level of detail is "
			"measured in these cells. Default: 1% of the bounding box diagonal."));
		par.addParam(RichAbsPerc("tolerance", diag / 50.0f, 0.0f, diag / 5.0f, "Tolerance",
			"Largest distance of the input from the wrap: the wrap settles at a third of this distance outside "
			"the input (so that concave creases down to about 40 degrees stay within it) and never crosses the "
			"input. At least the cell size. Default: 2% of the bounding box diagonal."));
		for (const char *name : kWrapModelOptions) addOption(par, name, name == std::string("lod_face_area") ? "cell^2" : QString());
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
			gdm::PipelineOptions options = volumeOptions(par);
			if (!par.getBool("seed_automatic")) {
				const Point3m p = par.getPoint3m("seed_point");
				options.seed.kind = gdm::SeedKind::point;
				options.seed.point = gdm::Vec3(p[0], p[1], p[2]);
			}
			readOptions(par, {"seed_radius"}, options);
			const gdm::Mesh mesh = gdm_meshlab::model_from_volume(
				par.getString("volume_file").toStdString(), options, progress, &log);
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
			gdm::PipelineOptions options = volumeOptions(par);
			readOptions(par, {"mode"}, options);
			options.seed.kind = gdm::SeedKind::mesh;
			options.seed.mesh = gdm_meshlab::to_gdm_seed(current->cm, &log);
			const gdm::Mesh mesh = gdm_meshlab::model_from_volume(
				par.getString("volume_file").toStdString(), options, progress, &log);
			flushLog();
			MeshModel *target = current;
			if (par.getBool("new_layer"))
				target = md.addNewMesh("", current->label() + " deformed", true);
			target->updateDataMask(MeshModel::MM_VERTQUALITY);
			gdm_meshlab::to_meshlab(mesh, target->cm);
			target->UpdateBoxAndNormals();
			return true;
		}
		case FP_GDM_SHRINK_WRAP: {
			MeshModel *current = md.mm();
			if (current == nullptr) return fail("no current layer to wrap");
			gdm::PipelineOptions m;
			readOptions(par, kWrapModelOptions, m);
			gdm::validate(m);
			gdm::WrapOptions w;
			w.cell_size = par.getAbsPerc("cell_size");
			w.tolerance = par.getAbsPerc("tolerance");
			w.a0 = m.deform.a0;
			w.a1 = m.deform.a1;
			w.a2 = m.deform.a2;
			w.lod_face_area = m.deform.lod_face_area;
			w.global_refinements = m.deform.global_refinements;
			w.max_cycles = m.deform.max_cycles;
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
