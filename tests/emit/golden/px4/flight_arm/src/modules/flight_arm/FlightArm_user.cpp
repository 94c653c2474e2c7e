// Written once by iface from flight_arm.iface: this file is yours to edit. `iface-lsp generate` never
// overwrites it, not even with --force. FlightArm.hpp and FlightArm.cpp are regenerated
// from the interface; when it changes, the compiler names the hooks below that no longer match.

#include "FlightArm.hpp"

#include <drivers/drv_hrt.h>

void FlightArm::on_start()
{
}

void FlightArm::on_parameters_updated()
{
	// _param_farm_max_speed.get(): FARM_MAX_SPEED
	// _param_farm_enabled.get(): FARM_ENABLED
	// _param_farm_retries.get(): FARM_RETRIES
	// _param_farm_start_mode.get(): FARM_START_MODE
	// _param_farm_gain.get(): FARM_GAIN
}

void FlightArm::on_arm_setpoint(const arm_setpoint_s &msg)
{
	(void)msg;
}

void FlightArm::on_arm_setpoint_override(const arm_setpoint_s &msg)
{
	(void)msg;
}

void FlightArm::on_cycle()
{
	// arm_status_s flight_arm_status{};
	// flight_arm_status.timestamp = hrt_absolute_time();
	// _flight_arm_status_pub.publish(flight_arm_status);
}
