// OpenGL 3.3 core declarations for the viewer. Functions are linked directly from libglvnd's
// libOpenGL (OpenGL::OpenGL), which exports every core entry point, so no loader is needed
// whether the context comes from EGL (headless) or from a window system (GLFW).
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
