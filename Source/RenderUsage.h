#pragma once
// jawari-render --help: every option, what it does, and the exit statuses.

inline constexpr const char* kRenderUsage =
    R"(jawari-render: render a jawari-scene/1 file, or a MIDI file played by the plugin, to a WAV file.

usage: jawari-render SCENE.json -o OUT.wav [options]
       jawari-render --midi SONG.mid -o OUT.wav [--preset NAME | --state FILE] [--set ID=VALUE]... [--duration S]
                     [--output-rate HZ] [--format int24|float] [--second-core] [--quiet]
       jawari-render --preset NAME | --state FILE -o OUT.wav --duration S   (the drone alone)

  -o, --output FILE       the WAV file to write (required)
  --method NAME           reference (the paper's configuration), or the plugin's voice (truncated
                          modes, oversampled, decimated; modes and rate automatic unless given)
                          with its contact solved by: realtime (energy-conserving Newton, the
                          default), quadratised (non-iterative), penalty (explicit at u^n)
  --modes M               number of modes (reference: N - 1 = M grid nodes)
  --rate HZ               internal simulation rate in Hz
  --duration S            seconds to render
  --output-rate HZ        sample rate of the WAV file
  --format NAME           the WAV's samples: int24 (24-bit integer, the default) or float (32-bit
                          IEEE float); a scene is normalised to a -1 dBFS peak in either
  --raw                   write the pickup quantity in SI units (m, m/s, N or Pa) as 32-bit float,
                          not normalised (implies --format float)
  --energy FILE.csv       log per output sample: time, energy H, contact energy, Newton iterations
  --quiet                 no progress bar and no summary
  -h, --help              this text

MIDI (instead of a scene file):
  --midi FILE.mid         a Standard MIDI File (type 0 or 1, its tempo map honoured) played through
                          the plugin's AudioProcessor; writes stereo at the plugin's level, its
                          latency removed (an event at t s sounds at sample t x rate). Without
                          --duration the file ends once the output has stayed below -100 dBFS for
                          0.5 s after the last event, at most 60 s after it
  --preset NAME           a factory preset, by its name or the part before the parenthesis
                          ("Default", "Paper centre obstacle", "Tanpura drone", "Sitar",
                          "Bass fret buzz", "Tanpura thread", "Sitar Sa-Pa"); the plugin's defaults (Default) without it
  --state FILE            a state saved by the plugin as XML (a user preset, .jawaripreset)
  --output-rate HZ        the rate the plugin runs at: 22050 to 192000 Hz (default 48000)
  --format NAME           int24 (the default): 24-bit, where samples at or beyond full scale are
                          clipped, with a warning that counts them; float: 32-bit float, every
                          sample as the plugin gives it, above full scale included
  --set ID=VALUE          a parameter set after the preset or state, in its own units (a switch 0
                          or 1, a choice by its index from 0; the ids: Source/Parameters.h), e.g.
                          --set sympathetic=0; may be given again
  --second-core           the plugin's "use a second core": half the strings stepped on another
                          thread (faster on two free cores; the same samples to the last bit)

The drone alone: --preset or --state without --midi (or with a MIDI file that holds no channel
events) plays a sound whose drone is on, for --duration seconds (required: a drone never falls
silent). A sound without the drone has nothing to play then, and is refused.

Options override the scene's `simulation` fields. A bad scene, MIDI file, preset, state or option
exits with status 2 and a message naming the problem; nothing is written then.
)";
