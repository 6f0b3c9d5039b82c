#include <polyloc/fusion/recording_fusion.hpp>

#include <optional>

namespace polyloc {

Mesh fuseRecording(RecordingReader& reader, const std::string& name, const FusionConfig& config,
                   const FrameSelection& selection, RecordingFusionStats& st, const std::function<void(double)>& progress) {
  config.validate();
  std::optional<TsdfFusion> fusion;
  forEachPosedFrame(
      reader, name, selection, config.min_depth, config.max_depth, st,
      [&](const PosedFrame& f) {
        if (!fusion) fusion.emplace(config, st.camera);
        fusion->integrate(f.depth.data(), f.world_T_body);
        st.path.push_back(f.world_T_body);
      },
      progress);
  st.fused = st.delivered;
  if (!fusion) return Mesh{};
  Mesh mesh = fusion->extract();
  st.fusion = fusion->stats();
  return mesh;
}

}  // namespace polyloc
