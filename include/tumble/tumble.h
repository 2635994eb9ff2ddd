/* tumble: rigid-body simulation for animation. Include this one header. */
#ifndef TUMBLE_H
#define TUMBLE_H

#include "tumble/export.h"
#include "tumble/version.h"
#include "tumble/status.h"
#include "tumble/ode.h"
#include "tumble/mass.h"
#include "tumble/body.h"
#include "tumble/keys.h"
#include "tumble/scene.h"
#include "tumble/effects.h"
#include "tumble/shape.h"
#include "tumble/contact_info.h"
#include "tumble/contact_events.h"
#include "tumble/run.h"
#include "tumble/scene_file.h"
#include "tumble/writer.h"
#include "tumble/accuracy.h"
#include "tumble/joints.h"

#endif
