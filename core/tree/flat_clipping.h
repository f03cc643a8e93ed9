// Flat clipping (paper §5.2, Fig. 12): evaluates the clip grammar of §3 for
// one sample without a stack, by a finite-state machine.
//
// States: P (processing: inside-outside tests and blending happen only
// here), S (skipping after a clip test succeeded: the rest of its union is
// short-circuited), SA (skipping by activate: a clip-path failed, skip the
// content it guards). Variables: d, the clip nesting depth; u, the number of
// enclosing groups whose '|' has not been reached (we are inside a clip-path
// test when u > 0); s, the stopping depth.
//
//   P  '(' : d+1, u+1                  S/SA '(' : d+1, u+1
//   P  '|' : u-1; -> SA, s = d         S  '|' : u-1; if d == s -> P
//   P  ')' : d-1                       S  ')' : if d == s: u == 0 -> P,
//   P  c1  : -> S, s = d                          else s = s-1 (an inner clip-path
//   P  f1  : blend; alpha = 1 -> done             succeeded, so does the outer union)
//                                                 then d-1
//                                      SA ')' : if d == s -> P; then d-1
//                                      SA '|' : u-1
//
// Here d counts the '(' seen and not yet closed, so '(' and its ')' are at
// the same depth and everything between them deeper.
//
// Transparency groups (core/paint/group.h) add a fourth state, SG (skipping the
// rest of a group's list: it can change no more), entered by the sampler
// with s = the depth inside the group, and left at the group's '}' (group
// delimiters count in d like '(' and ')'; sampling.h handles them). SG
// takes the clip delimiters as SA does, without leaving at ')'. c1 and f1 are a clip
// test and a fill that the current sample passes. A sample whose colour
// became opaque stops early (the transition to S with s = 0 of the paper,
// taken to its end).
#pragma once
#include <cstdint>

#include "core/hd.h"
#include "core/tree/shortcut_tree.h"

namespace mpvg {

enum FlatClipState : uint32_t { FLAT_P = 0, FLAT_S = 1, FLAT_SA = 2, FLAT_SG = 3 };

struct FlatClip {
  uint32_t state;
  int32_t d, u, s;
};

MPVG_HD_INLINE FlatClip flat_clip_start() { return FlatClip{FLAT_P, 0, 0, 0}; }

// Delimiter transition. kind is ENTRY_PUSH, ENTRY_ACTIVATE or ENTRY_POP.
MPVG_HD_INLINE void flat_clip_delimiter(FlatClip& m, uint32_t kind) {
  if (kind == ENTRY_PUSH) {
    m.d++;
    m.u++;
    return;
  }
  if (kind == ENTRY_ACTIVATE) {
    m.u--;
    if (m.state == FLAT_P) {
      // Reached '|' still processing: no clip test of this union passed.
      m.state = FLAT_SA;
      m.s = m.d;
    } else if (m.state == FLAT_S && m.d == m.s) {
      m.state = FLAT_P;
    }
    return;
  }
  // ENTRY_POP
  if (m.state == FLAT_S && m.d == m.s) {
    if (m.u == 0)
      m.state = FLAT_P;
    else
      m.s--;
  } else if (m.state == FLAT_SA && m.d == m.s) {
    m.state = FLAT_P;
  }
  m.d--;
}

// A clip test the sample passed (c1).
MPVG_HD_INLINE void flat_clip_pass(FlatClip& m) {
  m.state = FLAT_S;
  m.s = m.d;
}

}  // namespace mpvg
