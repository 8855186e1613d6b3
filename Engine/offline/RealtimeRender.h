#pragma once
// The scene's "realtime" method: the voice the plugin plays (Voice.h) at the scene's automatic
// quality; with other strings on the body (the sympathetic strings), one voice per string on one
// SharedBody, stepped as the instrument steps them. OFF.

#include "offline/OfflineRender.h"
#include "realtime/voice/Voice.h"

namespace jawari
{

// What every render reports about its solver before it runs (OfflineRender.cpp).
void describeSolver(ModalSolver& solver, double rateHz, RenderStats& stats);

// The voice a scene's "realtime" method plays: its automatic quality, the obstacles it can reach.
VoiceConfig voiceConfigFor(const Scene& scene);

// The scene by its "realtime" method, the voice's decimator latency removed, so output sample m is
// the pickup at t = m / output rate as the reference's is.
RenderResult renderRealtime(const Scene& scene, const RenderOptions& options);

}  // namespace jawari
