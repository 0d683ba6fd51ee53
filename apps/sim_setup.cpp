#include "sim_setup.hpp"

#include "codesign/config_reader.hpp"
#include "io/gym_config.hpp"
#include "io/mesh_config.hpp"

namespace codesign::app {

SimSetup read_sim_setup(const std::string& config_path) {
  io::TableReader root = config_path.empty() ? io::TableReader::from_string("", "(defaults)")
                                             : io::TableReader::from_file(config_path);
  SimSetup s;
  s.spec.model.material = io::read_material(root);
  const io::SceneSettings sc = io::read_scene(root);
  s.scene = sc.scene;
  s.spec.model.tip_region_mm = sc.tip_region_mm;
  s.solver = io::read_solver(root);
  s.spec.geometry = io::read_geometry(root);
  s.spec.mesh = io::read_mesh_options(root);
  {
    io::TableReader fibres = root.table("fibres");
    const io::FibreStiffness fs = io::read_fibre_stiffness(fibres);
    s.spec.model.fibre_axial_stiffness_uN = fs.axial_stiffness_uN;
    s.spec.model.fibres_tension_only = fs.tension_only;
    s.spec.fibres = io::read_fibre_layout(fibres);
    fibres.finish();
  }
  s.scenario = io::read_sim_scenario(root);
  s.task = coopt::read_task_config(root);
  s.codesign = coopt::read_codesign_config(root, s.task);
  {
    io::TableReader ppo = root.table("ppo");
    s.ppo = io::read_ppo_config(ppo, rl::paper_ppo_config());
    ppo.finish();
  }
  root.finish();
  return s;
}

}  // namespace codesign::app
