#include "engine/film_sensor.h"

#include "spectral/white_balance.h"

namespace rayproc {

SensorMatrix sensorMatrix(const FilmSensor& sensor, const spectral::ColorSpace& cs) {
    SensorMatrix s;
    if (sensor.passthrough()) return s;
    s.identity = false;
    const double ratio = sensor.exposureTime * sensor.iso / 100;
    spectral::Mat3 rgb; // RGB -> RGB: the identity without white balance (exactly: no round trip)
    for (int i = 0; i < 3; ++i) rgb.m[i][i] = 1;
    if (sensor.whiteBalance > 0) {
        const spectral::Mat3 w = spectral::bradfordAdaptation(
            spectral::daylightWhite(sensor.whiteBalance), spectral::chromaticityOf(cs.white));
        rgb = cs.xyzToRgb * (w * cs.rgbToXyz);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) s.m[i][j] = float(ratio * rgb.m[i][j]);
    return s;
}

void applySensor(const SensorMatrix& s, Image& img) {
    if (s.identity) return;
    for (std::size_t p = 0; p + 2 < img.pixels.size(); p += 3) {
        const float r = img.pixels[p], g = img.pixels[p + 1], b = img.pixels[p + 2];
        for (int i = 0; i < 3; ++i)
            img.pixels[p + std::size_t(i)] = s.m[i][0] * r + s.m[i][1] * g + s.m[i][2] * b;
    }
}

} // namespace rayproc
