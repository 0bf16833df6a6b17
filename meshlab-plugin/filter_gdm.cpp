// The plugin class: names, help, parameters and dispatch. The work is in
// gdm_bridge.cpp (CMeshO <-> gdm::Mesh and calls into the gdm core).
#include "filter_gdm.h"

#include <exception>
#include <map>
#include <stdexcept>
#include <vector>

#include "gdm/errors.h"
#include "filter_parameters.h"
#include "gdm_bridge.h"

namespace {

// One line: MeshLab sizes its dialog before the description wraps, so every
// extra line of description is a line of parameters cut off at the bottom.
const char *const kReference =
	"<br>Miller, Breen, Lorensen, O'Bara, Wozny: <b>Geometrically Deformed Models</b>, SIGGRAPH '91.";

using gdm_meshlab::Filter;
using gdm_meshlab::FilterParam;
using gdm_meshlab::ParamKind;

Filter filterOf(int id)
{
	switch (id) {
	case FilterGdmPlugin::FP_GDM_FROM_VOLUME: return Filter::from_volume;
	case FilterGdmPlugin::FP_GDM_DEFORM_MESH: return Filter::deform_mesh;
	default: return Filter::shrink_wrap;
	}
}

const gdm::OptionEntry<gdm::PipelineOptions> &catalogueOption(const std::string &name)
{
	if (const auto *o = gdm_meshlab::catalogue_option(name)) return *o;
	throw std::logic_error("no option " + name + " in the catalogue");
}

// A catalogue option as a parameter: its name, default, range and help.
void addOption(RichParameterList &par, const FilterParam &p)
{
	const auto &o = catalogueOption(p.name);
	const double value = p.own_default ? p.default_value : o.get(gdm::PipelineOptions{});
	const QString label = QString::fromStdString(gdm_meshlab::dialog_label(p));
	const QString help = QString::fromStdString(gdm_meshlab::dialog_help(o, p));
	const QString name = QString::fromStdString(o.name);
	switch (o.type) {
	case gdm::OptionType::real: par.addParam(RichFloat(name, static_cast<float>(value), label, help)); break;
	case gdm::OptionType::integer: par.addParam(RichInt(name, static_cast<int>(value), label, help)); break;
	case gdm::OptionType::boolean: par.addParam(RichBool(name, value != 0.0, label, help)); break;
	case gdm::OptionType::choice: {
		QStringList choices;
		for (const auto &c : o.choices) choices << QString::fromStdString(c);
		par.addParam(RichEnum(name, static_cast<int>(value), choices, label, help));
		break;
	}
	}
}

// The values last applied per filter: a reopened dialog shows them (the
// wrap's lengths excepted: they follow the layer's size).
std::map<int, RichParameterList> &lastUsed()
{
	static std::map<int, RichParameterList> values;
	return values;
}

void addParameters(RichParameterList &par, int id, const MeshModel *m)
{
	const float diag = m != nullptr && !m->cm.bbox.IsNull() ? m->cm.bbox.Diag() : 1.0f;
	for (const FilterParam &p : gdm_meshlab::filter_parameters(filterOf(id))) {
		const QString name = QString::fromStdString(p.name);
		const QString label = QString::fromStdString(p.label);
		const QString help = QString::fromStdString(p.help);
		switch (p.kind) {
		case ParamKind::volume_file:
			par.addParam(RichOpenFile(name, "", QStringList() << "*.mha" << "*.mhd" << "*.nrrd" << "*.nhdr" << "*.nii"
				<< "*.nii.gz" << "*.vtk" << "*.dcm" << "*", label, help));
			break;
		case ParamKind::boolean: par.addParam(RichBool(name, p.default_value != 0.0, label, help)); break;
		case ParamKind::real: par.addParam(RichFloat(name, static_cast<float>(p.default_value), label, help)); break;
		case ParamKind::point: par.addParam(RichPoint3f(name, Point3m(0, 0, 0), label, help)); break;
		case ParamKind::text: par.addParam(RichString(name, "", label, help)); break;
		case ParamKind::abs_perc:
			par.addParam(RichAbsPerc(name, diag * static_cast<float>(p.default_value), 0.0f, diag, label, help));
			break;
		case ParamKind::catalogue: addOption(par, p); break;
		}
	}
	const auto last = lastUsed().find(id);
	if (last == lastUsed().end()) return;
	for (const RichParameter &remembered : last->second)
		if (par.hasParameter(remembered.name()) && !remembered.value().isAbsPerc())
			par.setValue(remembered.name(), remembered.value());
}

// The pipeline's options from a dialog (or a script).
gdm::PipelineOptions readOptions(const RichParameterList &par, int id)
{
	gdm::PipelineOptions o;
	for (const FilterParam &p : gdm_meshlab::filter_parameters(filterOf(id))) {
		const QString name = QString::fromStdString(p.name);
		if (p.kind == ParamKind::catalogue) {
			const auto &c = catalogueOption(p.name);
			switch (c.type) {
			case gdm::OptionType::real: c.set(o, par.getFloat(name)); break;
			case gdm::OptionType::integer: c.set(o, par.getInt(name)); break;
			case gdm::OptionType::boolean: c.set(o, par.getBool(name) ? 1.0 : 0.0); break;
			case gdm::OptionType::choice: c.set(o, par.getEnum(name)); break;
			}
		} else if (p.name == "threshold_otsu") {
			o.threshold_otsu = par.getBool(name);
		} else if (p.name == "threshold") {
			o.threshold = par.getFloat(name);
		} else if (p.name == "seed_automatic" && !par.getBool(name)) {
			const Point3m s = par.getPoint3m("seed_point");
			o.seed.kind = gdm::SeedKind::point;
			o.seed.point = gdm::Vec3(s[0], s[1], s[2]);
		} else if (p.name == "more_options") {
			gdm_meshlab::apply_more_options(par.getString(name).toStdString(), o);
		}
	}
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
		return QString("A closed, 2-manifold, genus-0, self-intersection-free mesh of the object in a volume, as the "
			"gdm command makes it (Otsu's threshold and the automatic seed by default). Vertex quality = the cycle "
			"that created the vertex (Fig. 11).")
			+ kReference;
	case FP_GDM_DEFORM_MESH:
		return QString("The current layer (closed, 2-manifold) is the seed of a deformed model in a volume file: it "
			"grows inside the object or shrinks around it. Vertex quality = generation.")
			+ kReference;
	case FP_GDM_SHRINK_WRAP:
		return QString("Wraps the current layer (holes, several pieces, noise, point clouds) in a closed, 2-manifold, "
			"genus-0, self-intersection-free mesh: a sphere shrinks onto the layer's distance field (section 1). "
			"The log gives the estimate, the faces and the largest distances to the input.")
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
	addParameters(par, ID(action), m);
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
		lastUsed()[ID(action)] = par;
		switch (ID(action)) {
		case FP_GDM_FROM_VOLUME: {
			const gdm::PipelineOptions options = readOptions(par, ID(action));
			const gdm::Mesh mesh = gdm_meshlab::model_from_volume(
				gdm_meshlab::volume_path(par.getOpenFileName("volume_file").toStdString()), options, progress, &log);
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
			gdm::PipelineOptions options = readOptions(par, ID(action));
			options.seed.kind = gdm::SeedKind::mesh;
			options.seed.mesh = gdm_meshlab::to_gdm_seed(current->cm, &log);
			const gdm::Mesh mesh = gdm_meshlab::model_from_volume(
				gdm_meshlab::volume_path(par.getOpenFileName("volume_file").toStdString()), options, progress, &log);
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
			const gdm::PipelineOptions m = readOptions(par, ID(action));
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
			w.bridge = par.getAbsPerc("bridge");
			w.time_limit = par.getFloat("time_limit");
			w.memory_limit = par.getFloat("memory_limit");
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
