/* scene_canonical.h - the canonical text of a parsed scene and the strong ETag derived from it.
 * Two requests get the same tag exactly when the renderer would produce the same bytes. */
#ifndef LUCENTD_SCENE_CANONICAL_H
#define LUCENTD_SCENE_CANONICAL_H

#include "lucent.h"

/* Writes every field of scene, in a fixed order and number format; returns the length or -1 if cap
 * is too small. Call it before a stored mesh id is rewritten to its file path. */
int scene_canonical(const lucent_scene *scene, char *buf, size_t cap);
/* 64 lowercase hex digits: sha256 of the renderer build, the device name and the canonical scene. */
int scene_etag(const lucent_scene *scene, const char *device, char out[65]);

#endif
