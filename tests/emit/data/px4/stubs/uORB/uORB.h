// Test stub: topic metadata and ORB_ID as PX4 spells them.
#pragma once

struct orb_metadata {
	const char *o_name;
};
#define ORB_ID(_name) (&__orb_##_name)
