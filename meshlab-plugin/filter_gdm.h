// MeshLab filter plugin: Geometrically Deformed Models (Miller et al. 1991).
#ifndef GDM_FILTER_GDM_H
#define GDM_FILTER_GDM_H

#include <common/interfaces.h>

class FilterGdmPlugin : public QObject, public MeshFilterInterface
{
	Q_OBJECT
	MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
	Q_INTERFACES(MeshFilterInterface)

public:
	enum { FP_GDM_FROM_VOLUME, FP_GDM_DEFORM_MESH, FP_GDM_SHRINK_WRAP };

	FilterGdmPlugin();

	QString pluginName() const;
	QString filterName(FilterIDType filter) const;
	QString filterInfo(FilterIDType filter) const;
	FilterClass getClass(QAction *a);
	FILTER_ARITY filterArity(QAction *) const;
	int getPreConditions(QAction *) const;
	int postCondition(QAction *) const;
	int getRequirements(QAction *);
	void initParameterSet(QAction *, MeshModel &m, RichParameterList &par);
	void initParameterSet(QAction *, MeshDocument &md, RichParameterList &par);
	bool applyFilter(QAction *action, MeshDocument &md, const RichParameterList &par, vcg::CallBackPos *cb);

private:
	void initParameters(QAction *action, const MeshModel *m, RichParameterList &par);
	bool fail(const QString &message);
};

#endif
