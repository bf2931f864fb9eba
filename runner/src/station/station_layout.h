// Where the subject view, its 3D block view and the experimenter panel sit in
// the window, in pixels from the top left (ImGui's convention).
#ifndef BURRLAB_RUNNER_STATION_STATION_LAYOUT_H_
#define BURRLAB_RUNNER_STATION_STATION_LAYOUT_H_

namespace burrlab::runner {

struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
};

struct StationLayout {
  PixelRect trial;         // title, interval, time left, message
  PixelRect block;         // the 3D view of the block and burr
  PixelRect answers;       // force indicator, question and buttons
  PixelRect experimenter;  // the experimenter's panel

  // Subject column on the left (5/8 of the width), experimenter on the right.
  static StationLayout For(int width, int height);
};

}  // namespace burrlab::runner

#endif  // BURRLAB_RUNNER_STATION_STATION_LAYOUT_H_
