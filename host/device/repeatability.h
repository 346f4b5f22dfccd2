// Measuring a device's repeatability at a point: the table moved there, the point read N times with
// a move away and back before each reading (the device's CMD_REPEATABILITY).
#pragma once
#include <cstdint>

#include "digitizer.pb.h"
#include "host/device/session.h"

namespace dg::host {

// Moves the table to (x_nm, y_nm) at feed_um_s and waits until it stands there, within one motor
// step (`step_nm`, the table's resolution); DeviceError when the device refuses, alarms on the way,
// stops elsewhere or is still moving after timeout_ms.
void move_table_to(Session& session, int32_t x_nm, int32_t y_nm, uint32_t step_nm, uint32_t feed_um_s, int timeout_ms);

// Reads the current point `count` times (2..64); DeviceError when the device refuses or fails.
digitizer_Repeatability measure_repeatability(Session& session, uint32_t count);

}  // namespace dg::host
