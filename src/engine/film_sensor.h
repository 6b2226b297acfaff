// The film's sensor (Scene::sensor; pbrt-v4's "rgb" film and "cie1931" sensor): one 3x3 matrix
// applied to the image the film resolves, so the film keeps accumulating as it does. pbrt-v4's
// sensor turns radiance into XYZ times the imaging ratio, white balances it, and the film takes
// it to the colour space's RGB; rayproc's film holds that colour space's linear RGB in both
// modes (RGB mode: the colours as they are; spectral mode: its XYZ through the same matrix), so
// the sensor is  ratio * RGB<-XYZ * W * XYZ<-RGB  on the film's RGB, W the Bradford adaptation
// from the daylight white of the white balance temperature to the colour space's white
// (spectral/white_balance.h), or the identity without white balance.
#pragma once

#include "image/image.h"
#include "scene/scene.h"
#include "spectral/color_space.h"

namespace rayproc {

struct SensorMatrix {
    bool identity = true; // the passthrough sensor: the image is left to the bit
    float m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
};

SensorMatrix sensorMatrix(const FilmSensor& sensor, const spectral::ColorSpace& cs);

// Multiplies every pixel by the matrix (nothing for the identity).
void applySensor(const SensorMatrix& s, Image& img);

} // namespace rayproc
